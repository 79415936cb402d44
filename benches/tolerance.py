#!/usr/bin/env python3
"""`run --tolerance` against the default run on every bundled engine: the
models chosen and the time of one run (best of --runs, start-up included).

usage: python3 benches/tolerance.py [--runs 9]   (after cargo build --release)
"""
import argparse, glob, json, os, subprocess, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "target", "release", "enginedyn")


def best(engine, extra, runs):
    times, out = [], None
    for _ in range(runs):
        t0 = time.perf_counter()
        out = subprocess.run([BIN, "run", "--engine", engine, "--json", *extra],
                             capture_output=True, text=True, check=True)
        times.append(time.perf_counter() - t0)
    m = json.loads(out.stdout)["models"]
    return min(times), f"{m['kinematics']}, {m['rod_model']}, {m['grid_step_deg']}°"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=9)
    a = ap.parse_args()
    print("| engine | default | --tolerance 1e-2 | --tolerance 1e-3 |")
    print("| --- | --- | --- | --- |")
    for e in sorted(glob.glob(os.path.join(ROOT, "data", "*.toml"))):
        d = best(e, [], a.runs)
        t2 = best(e, ["--tolerance", "0.01"], a.runs)
        t3 = best(e, ["--tolerance", "0.001"], a.runs)
        print(f"| {os.path.basename(e)[:-5]} | {d[0]*1e3:.1f} ms | {t2[0]*1e3:.1f} ms ({t2[1]}) "
              f"| {t3[0]*1e3:.1f} ms ({t3[1]}) |")


if __name__ == "__main__":
    main()
