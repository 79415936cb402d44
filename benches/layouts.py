#!/usr/bin/env python3
"""The reader on the layouts other tools write: one cycle per column and
.xlsx workbooks, against the long layout of the bench files.

usage: benches/layouts.py [--cycles 60] [--rounds 5] [--repeat 3] [--copies 10]
                          [--xlsx-cycles 60] [--bin PATH] [--no-build] [--results FILE]

- One bench file from ../shared/bench/make_batch.py (the inline-6 diesel,
  --cycles cycles at 0.1°: columns cycle,crank_deg,pressure_bar) is written
  again, cell for cell the same text, as one cycle per column: the angle and
  one pressure column per cycle, tab-separated, once without a header (read
  with `--columns crank_deg,pressure_bar...`) and once with a numbered
  header (`crank_deg`, `pressure_bar_1` ...). And as an .xlsx workbook
  (openpyxl, write-only mode) in the per-column layout with the header,
  from the first --xlsx-cycles cycles.
- Parsing is timed as `enginedyn batch --engine E --parse-only --jobs 1
  FILE...` (hidden flag: every cell read and checked, each cycle's trace
  built and dropped), one process over --copies hard links of the file so
  start-up weighs little, start-up included. Reported per pressure value
  (M values/s) for each layout, and the per-column rate over the long
  layout's (target: at least 0.8).
- The workbook: enginedyn the same way (one process, --copies links)
  against pandas `read_excel` (openpyxl engine) and, when python-calamine
  is installed, pandas' calamine engine, each timed inside its own Python
  process after pandas is imported and one warm-up read (as the yardsticks
  of ../shared/bench time themselves); per workbook and per cell.
- Each measurement runs --rounds times, interleaved (enginedyn --repeat
  times in each round); medians, every run listed. Files are read before
  every round (page cache warm).
- Before timing, each layout is read once without --parse-only and its
  imep_bar compared with the long layout's: a reader that skipped columns
  would show here, not as a fast time.
- A layout this build cannot read is reported as "not supported by this
  build" with its error; the rest still runs.

Prints a Markdown report for benches/RESULTS.md; --results FILE also writes it.
"""
import argparse, csv, importlib.util, io, os, platform, shutil, statistics, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = os.path.join(ROOT, "..", "shared", "bench")
TARGET = os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target")
BIN = os.path.join(TARGET, "release", "enginedyn")


def sh(cmd, **kw):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, **kw)


def warm(paths):
    for f in paths:
        with open(f, "rb") as h:
            while h.read(1 << 20):
                pass


# ---------------------------------------------------------------------------
# The layouts


def per_column(long_path, d):
    """The long file's cells regrouped one cycle per column, text unchanged.
    Returns (no-header path, header path, cycles, angles per cycle, rows as floats)."""
    cycles = {}
    with open(long_path) as f:
        head = f.readline().strip().split(",")
        assert head == ["cycle", "crank_deg", "pressure_bar"], head
        for line in f:
            c, a, p = line.rstrip("\n").split(",")
            cycles.setdefault(c, ([], []))
            cycles[c][0].append(a)
            cycles[c][1].append(p)
    keys = list(cycles)
    angles = cycles[keys[0]][0]
    for k in keys:
        if cycles[k][0] != angles:
            sys.exit(f"cycle {k} of {long_path} has other angles than cycle {keys[0]}: no per-column layout")
    cols = [cycles[k][1] for k in keys]
    rows = ["\t".join([a] + [c[i] for c in cols]) for i, a in enumerate(angles)]
    bare = os.path.join(d, "percol.txt")
    with open(bare, "w") as f:
        f.write("\n".join(rows) + "\n")
    named = os.path.join(d, "percol_header.txt")
    with open(named, "w") as f:
        f.write("\t".join(["crank_deg"] + [f"pressure_bar_{j + 1}" for j in range(len(cols))]) + "\n")
        f.write("\n".join(rows) + "\n")
    return bare, named, len(keys), len(angles), angles, cols


def workbook(angles, cols, n, d):
    import openpyxl
    wb = openpyxl.Workbook(write_only=True)
    ws = wb.create_sheet("diagram")
    ws.append(["crank_deg"] + [f"pressure_bar_{j + 1}" for j in range(n)])
    for i, a in enumerate(angles):
        ws.append([float(a)] + [float(c[i]) for c in cols[:n]])
    path = os.path.join(d, "percol.xlsx")
    wb.save(path)
    return path


def links(path, copies, d):
    """`copies` hard links to path (a symlink or copy where links fail)."""
    stem, ext = os.path.splitext(os.path.basename(path))
    out = []
    for k in range(copies):
        p = os.path.join(d, f"{stem}_{k:03d}{ext}")
        if not os.path.exists(p):
            try:
                os.link(path, p)
            except OSError:
                shutil.copyfile(path, p)
        out.append(p)
    return out


# ---------------------------------------------------------------------------
# Timing


class Layout:
    def __init__(self, name, path, values, flags=()):
        self.name, self.path, self.values, self.flags = name, path, values, list(flags)
        self.files = []
        self.runs = []
        self.error = None
        self.imep = None


def batch_cmd(engine, files, flags, *extra):
    return [BIN, "batch", "--engine", engine, "--jobs", "1", *flags, *extra, *files]


def probe(engine, lay):
    """Reads the layout once with the whole pipeline; records its imep_bar or its error."""
    r = subprocess.run(batch_cmd(engine, [lay.path], lay.flags, "--csv"), capture_output=True, text=True)
    # A failed item still has its row, whose `error` cell says why (exit 1).
    rows = list(csv.DictReader(io.StringIO(r.stdout))) if r.stdout.strip() else []
    err = rows[0].get("error") if rows else None
    if r.returncode != 0 or not rows or err:
        msg = err or (r.stderr.strip().splitlines() or [f"exit {r.returncode}"])[-1]
        lay.error = msg.replace("|", "\\|")[:120]
        return
    lay.imep = float(rows[0]["imep_bar"])


def time_parse(engine, lay):
    t0 = time.perf_counter()
    r = subprocess.run(batch_cmd(engine, lay.files, lay.flags, "--parse-only"), capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if r.returncode != 0:
        lay.error = (r.stderr.strip().splitlines() or [f"exit {r.returncode}"])[-1].replace("|", "\\|")[:120]
        return None
    return dt / len(lay.files)


PANDAS = r"""
import sys, time
import pandas as pd
path, engine, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
pd.read_excel(path, engine=engine)  # warm-up
ts = []
for _ in range(n):
    t0 = time.perf_counter()
    df = pd.read_excel(path, engine=engine)
    ts.append(time.perf_counter() - t0)
print(" ".join(repr(t) for t in ts), df.shape[0] * df.shape[1])
"""


def time_pandas(path, engine, n):
    r = subprocess.run([sys.executable, "-c", PANDAS, path, engine, str(n)], capture_output=True, text=True)
    if r.returncode != 0:
        return None, (r.stderr.strip().splitlines() or ["failed"])[-1][:200]
    *ts, cells = r.stdout.split()
    return [float(t) for t in ts], int(cells)


def med(v):
    return statistics.median(v) if v else float("nan")


def main():
    global BIN
    ap = argparse.ArgumentParser()
    ap.add_argument("--cycles", type=int, default=60)
    ap.add_argument("--xlsx-cycles", type=int, default=60)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--copies", type=int, default=10)
    ap.add_argument("--bin", help=f"enginedyn binary (default {BIN}, built with cargo)")
    ap.add_argument("--no-build", action="store_true")
    ap.add_argument("--no-xlsx", action="store_true")
    ap.add_argument("--results")
    a = ap.parse_args()
    if a.bin:
        BIN = os.path.abspath(a.bin)
    elif not a.no_build:
        sh(["cargo", "build", "--release", "--quiet", "-p", "enginedyn"], cwd=ROOT)
    for mod in ("numpy", "pandas", "openpyxl"):
        if importlib.util.find_spec(mod) is None:
            sh([sys.executable, "-m", "pip", "install", "--quiet", mod])
    calamine = importlib.util.find_spec("python_calamine") is not None
    with tempfile.TemporaryDirectory() as d:
        sh([sys.executable, os.path.join(SHARED, "make_batch.py"), d, "--files", "1",
            "--cycles", str(a.cycles), "--step", "0.1"])
        engine = os.path.join(d, "engine.toml")
        long_path = os.path.join(d, "d0000.csv")
        bare, named, ncyc, nang, angles, cols = per_column(long_path, d)
        values = ncyc * nang
        sizes = {"long": os.path.getsize(long_path), "bare": os.path.getsize(bare)}
        lays = [
            Layout("long: cycle,crank_deg,pressure_bar (comma)", long_path, values),
            Layout("one cycle per column, no header: --columns crank_deg,pressure_bar...", bare, values,
                   ["--columns", "crank_deg,pressure_bar..."]),
            Layout("one cycle per column, header pressure_bar_1 ... (tab)", named, values),
        ]
        xl = None
        if not a.no_xlsx:
            nx = min(a.xlsx_cycles, ncyc)
            t0 = time.perf_counter()
            xpath = workbook(angles, cols, nx, d)
            write_s = time.perf_counter() - t0
            xl = Layout(f"workbook .xlsx, one cycle per column, {nx} cycles", xpath, nx * nang)
            sizes["xlsx"] = os.path.getsize(xpath)
        for lay in lays + ([xl] if xl else []):
            lay.files = links(lay.path, a.copies, d)
            probe(engine, lay)
        paths = [p for lay in lays + ([xl] if xl else []) for p in lay.files] + [BIN]
        pandas_runs = {"openpyxl": [], "calamine": []}
        pandas_err = {}
        cells = None
        for r in range(a.rounds):
            warm(paths)
            order = lays + ([xl] if xl else [])
            if r % 2:
                order = order[::-1]
            for _ in range(a.repeat):
                for lay in order:
                    if lay.error is None:
                        t = time_parse(engine, lay)
                        if t is not None:
                            lay.runs.append(t)
            if xl is not None:
                for eng in ("openpyxl", "calamine") if calamine else ("openpyxl",):
                    ts, c = time_pandas(xl.path, eng, 1)
                    if ts is None:
                        pandas_err[eng] = c
                    else:
                        pandas_runs[eng] += ts
                        cells = c
    # ---- report
    long_rate = values / med(lays[0].runs) / 1e6 if lays[0].runs else None
    out = [
        f"machine: {os.cpu_count()} cores, {platform.machine()}; python {platform.python_version()}; "
        f"enginedyn {BIN}",
        f"data: one make_batch.py file, {ncyc} cycles x {nang} angles at 0.1° ({values:,} pressure values, "
        f"long layout {sizes['long'] / 1e6:.1f} MB, per column {sizes['bare'] / 1e6:.1f} MB); "
        f"{a.rounds} interleaved rounds, enginedyn {a.repeat} times in each over {a.copies} links of the file "
        f"(one process, start-up included); medians",
        "",
        "| layout (`batch --parse-only --jobs 1`) | median s per file | M pressure values/s | imep_bar (full run) | every run (s per file) |",
        "| --- | --- | --- | --- | --- |",
    ]
    for lay in lays:
        if lay.error is not None or not lay.runs:
            out.append(f"| {lay.name} | not supported by this build: {lay.error} | | | |")
            continue
        m = med(lay.runs)
        out.append(f"| {lay.name} | {m:.4f} | {lay.values / m / 1e6:.1f} | {lay.imep!r} | "
                   f"{' '.join(f'{v:.4f}' for v in lay.runs)} |")
    out += ["", "| target | wanted | measured | met |", "| --- | --- | --- | --- |"]
    for lay in lays[1:]:
        if lay.runs and long_rate:
            ratio = lay.values / med(lay.runs) / 1e6 / long_rate
            same = lay.imep == lays[0].imep
            out.append(f"| {lay.name} / long, rate per pressure value | ≥ 0.8 | {ratio:.2f} | "
                       f"{'yes' if ratio >= 0.8 else 'no'} |")
            out.append(f"| {lay.name}: imep_bar equal to the long layout's | yes | "
                       f"{'yes' if same else f'no ({lay.imep!r})'} | {'yes' if same else 'no'} |")
        else:
            out.append(f"| {lay.name} / long, rate per pressure value | ≥ 0.8 | not supported by this build | no |")
    if xl is not None:
        ncells = xl.values + nang + (xl.values // nang) + 1  # pressures, angles, header row
        out += ["", f"workbook: {sizes['xlsx'] / 1e6:.1f} MB, {nang + 1} rows x {xl.values // nang + 1} "
                f"columns ({ncells:,} cells), written by openpyxl write-only in {write_s:.1f} s", "",
                "| reader | median s per workbook | M cells/s | vs enginedyn | every run (s) |",
                "| --- | --- | --- | --- | --- |"]
        ours = med(xl.runs) if xl.runs and xl.error is None else None
        if ours is None:
            out.append(f"| enginedyn batch --parse-only --jobs 1 (process, start-up included) | not supported by "
                       f"this build: {xl.error} | | | |")
        else:
            same = ""
            if xl.values == values and lays[0].imep is not None:
                same = "; equal to the long layout's" if xl.imep == lays[0].imep else "; NOT the long layout's"
            out.append(f"| enginedyn batch --parse-only --jobs 1 (process, start-up included; imep_bar {xl.imep!r}{same}) | "
                       f"{ours:.4f} | {ncells / ours / 1e6:.2f} | 1 | {' '.join(f'{v:.4f}' for v in xl.runs)} |")
        for eng, label in (("openpyxl", "pandas read_excel, openpyxl engine"),
                           ("calamine", "pandas read_excel, calamine engine (python-calamine)")):
            runs = pandas_runs[eng]
            if eng == "calamine" and not calamine:
                out.append(f"| {label} | python-calamine not installed | | | |")
            elif not runs:
                out.append(f"| {label} | failed: {pandas_err.get(eng, '?')} | | | |")
            else:
                m = med(runs)
                vs = f"{m / ours:.1f}x slower" if ours else "–"
                out.append(f"| {label} (in-process, after import and a warm-up read) | {m:.4f} | "
                           f"{ncells / m / 1e6:.2f} | {vs} | {' '.join(f'{v:.4f}' for v in runs)} |")
        if cells is not None:
            out.append(f"\npandas read {cells:,} cells (header row as column names).")
    report = "\n".join(out)
    print(report)
    if a.results:
        with open(a.results, "w") as f:
            f.write(report + "\n")


if __name__ == "__main__":
    main()
