#!/usr/bin/env python3
"""Two enginedyn binaries side by side on one batch: `--jobs 1` and
`--jobs 2`, run alternately, medians and every round's speed-up.

usage: benches/ab.py NEW_BIN OLD_BIN DIR [ROUNDS]
DIR holds engine.toml and d*.csv (../shared/bench/make_batch.py writes
them); build the old binary in a worktree of the older commit
(`git worktree add ../old COMMIT && cargo build --release` there).
Session 12 used it for the two-core figure (benches/RESULTS.md).
"""
import glob
import os
import statistics
import subprocess
import sys
import time


def main():
    new, old, d = sys.argv[1:4]
    rounds = int(sys.argv[4]) if len(sys.argv) > 4 else 11
    files = sorted(glob.glob(os.path.join(d, "d*.csv")))
    engine = os.path.join(d, "engine.toml")
    for f in files:
        open(f, "rb").read()
    bins = {"new": new, "old": old}
    res = {(b, j): [] for b in bins for j in (1, 2)}
    for _ in range(rounds):
        for b, exe in bins.items():
            for j in (1, 2):
                t = time.perf_counter()
                subprocess.run([exe, "batch", "--engine", engine, *files, "--jobs", str(j), "--csv"], check=True, capture_output=True)
                res[(b, j)].append(time.perf_counter() - t)
    for b in bins:
        one, two = statistics.median(res[(b, 1)]), statistics.median(res[(b, 2)])
        ratios = " ".join(f"{a / c:.2f}" for a, c in zip(res[(b, 1)], res[(b, 2)]))
        print(f"{b}: jobs1 {one:.4f} s, jobs2 {two:.4f} s, speed-up {one / two:.3f}; per round {ratios}")


if __name__ == "__main__":
    main()
