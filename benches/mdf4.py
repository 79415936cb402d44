#!/usr/bin/env python3
"""The MDF4 reader against the CSV reader on the same samples.

usage: benches/mdf4.py [--cycles 60] [--rounds 5] [--copies 10] [--bin PATH]
                        [--before PATH] [--callgrind]
       (with the virtual environment's python: numpy and asammdf)

- One bench file from ../shared/bench/make_batch.py (the inline-6 diesel,
  --cycles cycles at 0.1°) is written again as an MDF4 file (asammdf,
  version 4.10): an angle master `crank_deg` in degrees that runs on over
  the cycles, and one `pressure` channel in bar, float64, one channel
  group, uncompressed; again compressed as asammdf's `compression=2`
  writes it (transposed deflate, `##DZ` blocks under a data list); and as
  a CSV of the same two columns (the angle running on too, so all go
  through the same cut at firing TDC).
- Before timing, each is read once with `run --json` and their IMEP
  compared: equal to the bit, or the bench stops.
- Parsing is timed as `enginedyn batch --parse-only --jobs 1` over --copies
  hard links of each file (one process, start-up included), --rounds
  times, alternating; medians. Reported per pressure value (M values/s)
  and the MDF4 rate over the CSV's.
- `--before PATH`: a second build (the one before a change) timed in the
  same rounds, alternating with the first, and reported beside it.
- `--callgrind`: each build's instructions on one file of each layout
  (`valgrind --tool=callgrind`, start-up included), per pressure value:
  figures a shared machine does not move.

Prints a Markdown table.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = "/work/shared/bench" if os.path.isdir("/work/shared/bench") else os.path.join(ROOT, "..", "shared", "bench")
BIN = os.path.join(ROOT, "target", "release", "enginedyn")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cycles", type=int, default=60)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--copies", type=int, default=10)
    ap.add_argument("--bin", default=BIN)
    ap.add_argument("--before", help="a second build, timed in the same rounds")
    ap.add_argument("--callgrind", action="store_true", help="instructions per value (valgrind)")
    a = ap.parse_args()
    import asammdf
    import numpy as np

    d = tempfile.mkdtemp(prefix="edmdf_")
    subprocess.run(
        [sys.executable, os.path.join(SHARED, "make_batch.py"), d, "--files", "1", "--cycles", str(a.cycles)],
        check=True,
        capture_output=True,
    )
    engine = os.path.join(d, "engine.toml")
    src = next(os.path.join(d, f) for f in os.listdir(d) if f.endswith(".csv"))
    rows = [r for r in open(src).read().splitlines() if r and not r.startswith("#")]
    head = rows[0].split(",")
    data = np.array([r.split(",") for r in rows[1:]], dtype=float)
    angle = np.arange(len(data)) / 10.0
    p = data[:, head.index("pressure_bar")]
    csv = os.path.join(d, "run_on.csv")
    cells = [r.split(",")[head.index("pressure_bar")] for r in rows[1:]]
    with open(csv, "w") as f:
        # The bench file's own pressure text; the angle to its 0.1°.
        f.write("crank_deg,pressure_bar\n")
        f.writelines(f"{k / 10:.1f},{c}\n" for k, c in enumerate(cells))
    mf4 = os.path.join(d, "run_on.mf4")
    m = asammdf.MDF(version="4.10")
    # An angle master (sync type 2), as an indicating system writes it.
    m.append([asammdf.Signal(p, angle, name="pressure", unit="bar", master_metadata=("Crank angle", 2))])
    m.save(mf4, overwrite=True)
    mdz = os.path.join(d, "run_on_dz.mf4")
    m.save(mdz, overwrite=True, compression=2)
    files = (csv, mf4, mdz)
    names = {csv: "CSV, angle running on", mf4: "MDF4, angle master, float64", mdz: "MDF4 compressed (transposed deflate)"}
    bins = [("after", a.bin)] + ([("before", a.before)] if a.before else [])
    want = None
    for _, b in bins:
        for f in files:
            r = subprocess.run([b, "run", "--engine", engine, "--diagram", f, "--json"], capture_output=True, text=True)
            if r.returncode != 0:
                print(f"{os.path.basename(f)}: exit {r.returncode}: {r.stderr.strip()}")
                return 1
            imep = json.loads(r.stdout)["imep_bar"]
            want = imep if want is None else want
            if imep != want:
                print(f"IMEP differs: {imep} against {want}")
                return 1
    links = {}
    for f in files:
        links[f] = []
        for k in range(a.copies):
            link = f"{f}.{k}{os.path.splitext(f)[1]}"
            os.link(f, link)
            links[f].append(link)
    times = {(b, f): [] for b, _ in bins for f in files}
    for _ in range(a.rounds):
        for b, path in bins:
            for f in files:
                for x in links[f]:
                    open(x, "rb").read()
                t = time.perf_counter()
                subprocess.run([path, "batch", "--engine", engine, "--parse-only", "--jobs", "1", *links[f]], check=True, capture_output=True)
                times[(b, f)].append(time.perf_counter() - t)
    values = len(p) * a.copies
    rate = {k: values / statistics.median(t) / 1e6 for k, t in times.items()}
    instr = {}
    if a.callgrind:
        for b, path in bins:
            for f in files:
                r = subprocess.run(
                    ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", path, "batch", "--engine", engine, "--parse-only", "--jobs", "1", f],
                    capture_output=True, text=True, check=True,
                )
                n = next(int(x.split(":")[1].replace(",", "")) for x in r.stderr.splitlines() if "Collected :" in x)
                instr[(b, f)] = n / len(p)
    print(f"{a.cycles} cycles at 0.1° ({len(p)} pressure values a file), {a.copies} copies, {a.rounds} rounds, medians; IMEP equal ({want} bar)\n")
    print("| build | layout | M values/s | instructions a value | every run (s) |")
    print("| --- | --- | --- | --- | --- |")
    for b, _ in bins:
        for f in files:
            i = f"{instr[(b, f)]:.0f}" if (b, f) in instr else "–"
            print(f"| {b} | {names[f]} | {rate[(b, f)]:.1f} | {i} | {', '.join(f'{x:.3f}' for x in times[(b, f)])} |")
    print()
    for b, _ in bins:
        for f, what in ((mf4, "MDF4"), (mdz, "compressed MDF4")):
            ratio = f"{what} / CSV rate ({b}): {rate[(b, f)] / rate[(b, csv)]:.2f}"
            if (b, csv) in instr:
                ratio += f"; by instructions {instr[(b, csv)] / instr[(b, f)]:.2f}"
            print(ratio)
    return 0


if __name__ == "__main__":
    sys.exit(main())
