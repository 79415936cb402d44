#!/usr/bin/env python3
"""What reading a diagram costs before any parsing: the system's copy out
of the page cache, file by file, in reads of a given size (the figure
behind session 21's reading beside the parse, benches/RESULTS.md).

usage: benches/read_cost.py [--block 65536] [--rounds 3] FILE [FILE ...]

Each round reads every file once (warm page cache) with os.readv into one
buffer; prints ms a file, wall and system time.
"""
import argparse
import os
import time


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--block", type=int, default=1 << 16)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("files", nargs="+")
    a = ap.parse_args()
    buf = memoryview(bytearray(a.block))
    for f in a.files:
        open(f, "rb").read()
    for _ in range(a.rounds):
        t0, c0 = time.perf_counter(), os.times()
        for f in a.files:
            fd = os.open(f, os.O_RDONLY)
            while os.readv(fd, [buf]) > 0:
                pass
            os.close(fd)
        t1, c1 = time.perf_counter(), os.times()
        n = len(a.files)
        print(f"reads of {a.block} bytes: {(t1 - t0) / n * 1e3:.3f} ms a file, "
              f"system {(c1.system - c0.system) / n * 1e3:.3f} ms")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
