#!/usr/bin/env python3
"""Checks generated report folders: every SVG parses as XML and names the
series it should, draws its curves between whole pixels and ends an angle
axis on 720 (or 360); report.html inlines every chart and its internal
links resolve. usage: check_reports.py DIR... (each a `run --out` folder)."""
import os, re, sys, xml.dom.minidom

EXPECT = {
    "pressure.svg": ["p(φ)", "p–V"],
    "kinematics.svg": ["A = x/R", "B = v/(Rω)", "C = a/(Rω²)"],
    "forces.svg": ["gas P_g", "inertia P_j", "side thrust N", "tangential T"],
    "torque.svg": ["cylinder 1, indicated", "engine (", "mean, indicated"],
    "journal_torques.svg": ["journal after throw 1"],
    "crankpin_polar.svg": ["pin load"],
    "flywheel.svg": ["E(φ)"],
    "harmonics.svg": ["cylinder 1", "engine"],
    "heat_release.svg": ["dQ/dφ", "mass fraction burned", "CA50", "Savitzky-Golay"],
}
# Charts over the burn window only (−90…120°), not the whole cycle: their
# angle axis does not end on a dead centre.
WINDOWED = {"heat_release.svg"}
# Charts of an engine file with [torsion] (run's torsion section): checked
# when the folder has them, and then the page must show them.
TORSION = {
    "campbell.svg": ["mode 1", "resonance", "engine speed (rpm)"],
    "torsion.svg": ["all orders (half peak-to-peak)", "largest section"],
}


def check_curves(p, doc, words, whole_cycle=True):
    """Curves drawn between whole pixels (no stair-steps), and an angle
    axis that ends on its labelled dead centre (720 or 360)."""
    problems = 0
    longest = max(
        (l.getAttribute("points").split() for l in doc.getElementsByTagName("polyline")),
        key=len,
        default=[],
    )
    if len(longest) > 100:
        coords = [float(c) for pt in longest for c in pt.split(",")]
        whole = sum(1 for c in coords if c == int(c))
        if whole > len(coords) // 2:
            print(f"{p}: {whole} of {len(coords)} curve coordinates on whole pixels (stair-steps)")
            problems += 1
    labels = [t.firstChild.data.strip() for t in doc.getElementsByTagName("text") if t.firstChild]
    if whole_cycle and "crank angle" in words and not ({"720", "360"} & set(labels)):
        print(f"{p}: the angle axis does not end on a labelled 720 or 360")
        problems += 1
    return problems


def main():
    problems = 0
    for d in sys.argv[1:]:
        expect = dict(EXPECT)
        expect.update({n: t for n, t in TORSION.items() if os.path.exists(os.path.join(d, n))})
        for name, texts in expect.items():
            p = os.path.join(d, name)
            try:
                doc = xml.dom.minidom.parse(p)
            except Exception as e:  # any parse failure is the finding
                print(f"{p}: does not parse: {e}")
                problems += 1
                continue
            words = " ".join(t.firstChild.data for t in doc.getElementsByTagName("text") if t.firstChild)
            for t in texts:
                if t not in words:
                    print(f"{p}: no series or label `{t}`")
                    problems += 1
            if not doc.getElementsByTagName("polyline") and not doc.getElementsByTagName("path"):
                print(f"{p}: draws no curve")
                problems += 1
            problems += check_curves(p, doc, words, name not in WINDOWED)
        acc = os.path.join(d, "accuracy.svg")
        if os.path.exists(acc):
            try:
                doc = xml.dom.minidom.parse(acc)
                words = " ".join(t.firstChild.data for t in doc.getElementsByTagName("text") if t.firstChild)
                for t in ["Pareto front", "grid_step", "kinematics", "rod_model"]:
                    if t not in words:
                        print(f"{acc}: no series `{t}`")
                        problems += 1
            except Exception as e:
                print(f"{acc}: does not parse: {e}")
                problems += 1
            head = open(os.path.join(d, "accuracy.csv"), encoding="utf-8").readline()
            if not head.startswith("study,setting,time_s,max_relative_error,"):
                print(f"{d}/accuracy.csv: header {head.strip()!r}")
                problems += 1
        html = open(os.path.join(d, "report.html"), encoding="utf-8").read()
        ids = set(re.findall(r'id="([^"]+)"', html))
        for name in expect:
            if name[:-4] not in ids:
                print(f"{d}/report.html: chart {name} is not on the page")
                problems += 1
        for href in re.findall(r'(?:href|src)="([^"]+)"', html):
            if href.startswith("#"):
                ok = href[1:] in ids
            else:
                ok = os.path.exists(os.path.join(d, href))
            if not ok:
                print(f"{d}/report.html: link {href} does not resolve")
                problems += 1
    print(f"{problems} report problems in {len(sys.argv) - 1} folders")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
