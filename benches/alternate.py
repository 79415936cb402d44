#!/usr/bin/env python3
"""Builds of enginedyn timed against each other on the same `batch`, runs
alternating, for the A/B figures of benches/RESULTS.md that no other
bench script gives (an MDF4 window size, a hash experiment, a build flag).

usage: benches/alternate.py --engine TOML [--rounds 21] [--args=--parse-only]
                            BIN [BIN ...] -- FILE [FILE ...]

Each round runs `BIN batch --engine TOML --jobs 1 --out TMPDIR ARGS FILE...`
once for every build in turn (one process, start-up included); prints the
median, first quartile and minimum wall time of each build.
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time


def main():
    argv = sys.argv[1:]
    if "--" not in argv:
        print(__doc__)
        return 2
    cut = argv.index("--")
    ap = argparse.ArgumentParser()
    ap.add_argument("--engine", required=True)
    ap.add_argument("--rounds", type=int, default=21)
    ap.add_argument("--args", default="")
    ap.add_argument("bins", nargs="+")
    a = ap.parse_args(argv[:cut])
    files = argv[cut + 1:]
    for f in files:
        open(f, "rb").read()  # page cache warm
    out = tempfile.mkdtemp(prefix="edalt_")
    times = {b: [] for b in a.bins}
    for _ in range(a.rounds):
        for b in a.bins:
            cmd = [b, "batch", "--engine", a.engine, "--jobs", "1", "--out", out, *a.args.split(), *files]
            t = time.perf_counter()
            subprocess.run(cmd, capture_output=True, check=True)
            times[b].append(time.perf_counter() - t)
    for b in a.bins:
        v = sorted(times[b])
        print(f"{b}: median {statistics.median(v) * 1e3:.2f} ms, q1 {v[len(v) // 4] * 1e3:.2f}, "
              f"min {v[0] * 1e3:.2f} ({a.rounds} runs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
