#!/usr/bin/env python3
"""The Python package against the CLI, in one run (issue 28, part 6).

usage: benches/python.py [--files 200] [--cycles 10] [--rounds 5]
       (run with the virtual environment's python, the package installed
       with `maturin develop --release`, the CLI built with `cargo build --release`)

Files come from ../shared/bench/make_batch.py (the batch bench's
six-cylinder diesel), read once before timing. Each figure is the median
of --rounds rounds, the programs interleaved:

- per file: `enginedyn batch --jobs 1 --csv` (one process, start-up
  included) against `Session.batch(files, jobs=1)` (in process, the
  session built outside the timing) and against `Session.analyse(path)`
  file by file (what `run` computes: the report curves too);
- two threads: two Python threads each `Session.batch(half, jobs=1)`,
  against one thread on all of them;
- Dask: `map_campaign` on a LocalCluster of 2 single-thread worker
  processes (started outside the timing) at 50 files a task, against the
  in-process `Session.batch(files, jobs=2)` writing the same parts;
- Parquet: `batch --jobs 1` with `--parquet DIR` against without.

Prints a Markdown table.
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = os.path.join(ROOT, "..", "shared", "bench")
BIN = os.path.join(ROOT, "target", "release", "enginedyn")


def timed(f):
    t = time.perf_counter()
    f()
    return time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--files", type=int, default=200)
    ap.add_argument("--cycles", type=int, default=10)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--data", help="a folder make_batch.py already wrote (its engine.toml and files): not made again")
    a = ap.parse_args()
    import enginedyn as ed
    from distributed import Client, LocalCluster
    from enginedyn.dask import map_campaign

    if a.data:
        work = a.data
    else:
        work = tempfile.mkdtemp(prefix="edpy_")
        subprocess.run(
            [sys.executable, os.path.join(SHARED, "make_batch.py"), work, "--files", str(a.files), "--cycles", str(a.cycles)],
            check=True,
            capture_output=True,
        )
    engine = os.path.join(work, "engine.toml")
    files = sorted(os.path.join(work, f) for f in os.listdir(work) if f.endswith(".csv"))[: a.files]
    for f in files:
        open(f, "rb").read()
    s = ed.Session(ed.Engine.from_toml(engine))
    half = len(files) // 2

    def cli(*extra):
        subprocess.run([BIN, "batch", "--engine", engine, *files, "--jobs", "1", *extra], check=True, capture_output=True)

    def two_threads():
        ts = [threading.Thread(target=s.batch, args=(part, 1)) for part in (files[:half], files[half:])]
        for t in ts:
            t.start()
        for t in ts:
            t.join()

    times = {
        k: []
        for k in (
            "cli",
            "cli_json",
            "py_batch",
            "py_analyse",
            "one_thread",
            "two_threads",
            "inproc",
            "dask",
            "cli_plain",
            "cli_parquet",
            "cli_json_parquet",
        )
    }
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
        map_campaign(client, s, files[:4], os.path.join(work, "warm"), files_per_task=2)
        for r in range(a.rounds):
            times["cli"].append(timed(lambda: cli("--csv")))
            times["cli_json"].append(timed(lambda: cli("--json")))
            times["py_batch"].append(timed(lambda: s.batch(files, jobs=1)))
            times["py_analyse"].append(timed(lambda: [s.analyse(f) for f in files]))
            times["one_thread"].append(timed(lambda: s.batch(files, jobs=1)))
            times["two_threads"].append(timed(two_threads))
            out_in = os.path.join(work, f"inproc{r}")
            times["inproc"].append(timed(lambda: s.batch(files, jobs=2).write_parquet(out_in)))
            out_dask = os.path.join(work, f"dask{r}")
            times["dask"].append(timed(lambda: map_campaign(client, s, files, out_dask, files_per_task=50)))
            times["cli_plain"].append(timed(lambda: cli("--csv")))
            times["cli_parquet"].append(timed(lambda: cli("--parquet", os.path.join(work, f"pq{r}"))))
            times["cli_json_parquet"].append(timed(lambda: cli("--json", "--parquet", os.path.join(work, f"pqj{r}"))))
    m = {k: statistics.median(v) for k, v in times.items()}
    n = len(files)
    rows = [
        ("CLI `batch --jobs 1 --csv`, ms per file", 1e3 * m["cli"] / n, ""),
        ("CLI `batch --jobs 1 --json` (summary.json per file: inputs hashed), ms per file", 1e3 * m["cli_json"] / n, ""),
        ("Python `Session.batch(jobs=1)` (summary.json per file), ms per file", 1e3 * m["py_batch"] / n, f"{m['py_batch'] / m['cli_json']:.3f} × CLI --json (target ≤ 1.10); {m['py_batch'] / m['cli']:.3f} × CLI --csv"),
        ("Python `Session.analyse(path)` per file (report curves too), ms", 1e3 * m["py_analyse"] / n, f"{m['py_analyse'] / m['cli']:.3f} × CLI batch"),
        ("two Python threads / one thread", m["one_thread"] / m["two_threads"], "target ≥ 1.7"),
        ("Dask, 2 workers, 50 files a task / in-process jobs=2 (files/s)", m["inproc"] / m["dask"], "target ≥ 0.85"),
        ("`batch --json --parquet` / `batch --json`, --jobs 1 (the parts' writing)", m["cli_json_parquet"] / m["cli_json"], "target ≤ 1.05"),
        ("`batch --parquet` / `batch --csv`, --jobs 1 (the writing and each diagram's SHA-256)", m["cli_parquet"] / m["cli_plain"], ""),
    ]
    print(f"{n} files of {a.cycles} cycles (six-cylinder diesel, 0.1° data), {a.rounds} rounds, medians\n")
    print("| figure | value | against |\n| --- | --- | --- |")
    for name, v, note in rows:
        print(f"| {name} | {v:.3f} | {note} |")
    print("\nevery run (s):")
    for k, v in times.items():
        print(f"- {k}: " + ", ".join(f"{x:.3f}" for x in v))


if __name__ == "__main__":
    main()
