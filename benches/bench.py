#!/usr/bin/env python3
"""enginedyn against the Python yardsticks of ../shared/bench: same files,
same run, the protocol of issue 8.

usage: benches/bench.py [--files 40] [--cycles 50] [--rounds 9] [--repeat 3] [--results FILE]
                        [--before BIN] [--callgrind]

- Files come from ../shared/bench/make_batch.py and are read before any
  timing (page cache warm). They are read again (with the enginedyn binary)
  before every round and every group of enginedyn runs: on this VM
  something outside the guest evicts the page cache slowly even with
  gigabytes free (about 1 % of the batch every 10 s), so files read only
  once at the start are partly read from disk again minutes later. The
  blocks read from disk during the timed enginedyn runs (/proc/vmstat
  pgpgin) are reported.
- Each program runs --rounds times, interleaved; medians are compared and
  every run is recorded. enginedyn's runs are short (a third of a second),
  so each round runs them --repeat times: the medians then rest on
  rounds x repeat runs, which this VM's slow phases (a run taking 1.5 times
  as long as the one before) move less.
- enginedyn is timed as one `batch` process over all files, start-up
  included: --jobs 1, --jobs 2, and the parse floor
  (the hidden --parse-only: every cell read and checked, nothing computed).
- The yardsticks time themselves (after a warm-up file), with
  OPENBLAS_CORETYPE and OPENBLAS_L2_SIZE unset in their command alone.
- Compute throughput: the time the --jobs 1 batch spends after parsing
  (putting each file's traces on the grid, the analysis and its summary
  row), per cylinder-sample (one grid point of one cylinder). enginedyn
  measures it inside the timed runs, around those stages, with the
  monotonic clock (the hidden --stage-times; the --jobs 2 runs carry it
  too, so the two-core ratio compares like with like); the median over
  every run is used. For comparison, the whole-process difference (full -
  parse floor, back to back in alternating order, median of the paired
  differences) is also reported: it is the same quantity as a small
  difference of two large, noisy times, and single differences on this VM
  swing by more than the compute itself (from -3.2 to +4.3 ms a file
  against about 0.6).
- Serial and parallel batches must give byte-identical summary.csv.
- The machine's own two-core speed-up, for comparison: two independent
  `batch --jobs 1` processes started together, each on half the files
  (no shared process, pool or queue), timed until both finish. On a VM
  whose two vCPUs share physical cores with other guests this is what any
  parallel batch can hope for; `--jobs 2` is reported against it.
- And the machine's speed-up on work that shares nothing at all, not even
  memory traffic: a pure-Python loop run in one process alone, then in two
  processes at once (each timed inside the process, start-up excluded).
  If the two vCPUs were two physical cores this would be 2.0 every time;
  when they share a core (its two hardware threads, or with another guest)
  it is less.

- One core, strictly: `--jobs 1` lets a diagram's BLAKE3 run on a thread
  of its own while a core is idle (issue 42), so the `--jobs 1` batch may
  use a second core for the hash. The same command pinned to one core
  (`taskset -c 0`: the process then sees one core and hashes inline) is
  timed too, and the yardstick ratios are given for both.
- --before BIN: a second build (the commit before a change) timed in the
  same rounds, each of its commands beside the new one's; its summary.csv
  compared with the new one's (identical, or the columns that differ).
- --callgrind: instructions (valgrind) of one file through each build,
  whole and parse floor: the figures to trust on a shared machine.

Prints a Markdown report; --results FILE also writes it there.
"""
import argparse, multiprocessing, os, platform, shutil, statistics, subprocess, sys, tempfile, time, tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = os.path.join(ROOT, "..", "shared", "bench")
BIN = os.path.join(ROOT, "target", "release", "enginedyn")

TARGETS = [
    ("one core vs yardstick.py (pandas)", "x_slow_1", 9.0),
    ("one core vs yardstick_fast.py (pyarrow)", "x_fast_1", 2.5),
    ("one core pinned (taskset -c 0) vs yardstick.py (pandas)", "x_slow_pin", 9.0),
    ("one core pinned (taskset -c 0) vs yardstick_fast.py (pyarrow)", "x_fast_pin", 2.5),
    ("two cores vs yardstick.py", "x_slow_2", 9.0),
    ("two cores vs yardstick_fast.py", "x_fast_2", 3.6),
    ("compute after parsing, M cylinder-samples/s per core", "msamples", 50.0),
    ("whole pipeline / parse floor (at most)", "floor_ratio", 1.2),
    ("whole pipeline pinned to one core / parse floor (at most)", "floor_ratio_pin", 1.2),
    ("parse floor, GB/s a core", "floor_gbs", 2.0),
    ("two cores / one core speed-up", "scaling", 1.8),
]
LOWER = ("floor_ratio", "floor_ratio_pin")


def sh(cmd, env=None):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, env=env)


def yardstick(script, files):
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE")}
    engine = os.path.join(os.path.dirname(files[0]), "engine.toml")
    out = sh([sys.executable, os.path.join(SHARED, script), engine, *files], env).stdout
    return float(out.split(" s per file")[0])


def batch(files, dirname, out, *extra, exe=None, pin=False):
    """The `enginedyn batch` command over `files` into a fresh folder `out`
    (`pin`: on one core, through taskset)."""
    shutil.rmtree(out, ignore_errors=True)
    cmd = [exe or BIN, "batch", "--engine", os.path.join(dirname, "engine.toml"), *files, "--out", out, *extra]
    return (["taskset", "-c", "0"] if pin else []) + cmd


def ours(files, dirname, *extra, exe=None, pin=False):
    """Times one `enginedyn batch` over `files`: (s per file, summary.csv,
    and with --stage-times in `extra` the (grid, analysis) s per file that
    enginedyn measured inside the run, else None)."""
    out = os.path.join(dirname, "out")
    cmd = batch(files, dirname, out, *extra, exe=exe, pin=pin)
    t0 = time.perf_counter()
    done = sh(cmd)
    dt = time.perf_counter() - t0
    stages = None
    if "--stage-times" in extra:
        # "stage times over N diagrams: grid G s, analysis A s"
        line = next(l for l in done.stderr.splitlines() if l.startswith("stage times"))
        grid = float(line.split("grid ")[1].split(" s")[0])
        analysis = float(line.split("analysis ")[1].split(" s")[0])
        stages = (grid / len(files), analysis / len(files))
    with open(os.path.join(out, "summary.csv"), "rb") as f:
        return dt / len(files), f.read(), stages


def warm(paths):
    """Reads every path once, so the timed runs find them in the page cache."""
    for f in paths:
        with open(f, "rb") as h:
            while h.read(1 << 20):
                pass


def disk_kb():
    """Kilobytes read from block devices since boot (Linux), else 0."""
    try:
        with open("/proc/vmstat") as f:
            return next(int(line.split()[1]) for line in f if line.startswith("pgpgin "))
    except (OSError, StopIteration):
        return 0


def spin(n):
    x = 0
    for i in range(n):
        x += i * i & 7
    return x


def timed_spin(q, n):
    t0 = time.perf_counter()
    spin(n)
    q.put(time.perf_counter() - t0)


def cpu_probe(n=2_000_000):
    """Two-core speed-up of a pure-Python loop: 2 t1 / t2, with t1 the loop's
    time in one process alone and t2 the slower of two processes at once."""
    ctx = multiprocessing.get_context()

    def run(k):
        q = ctx.Queue()
        procs = [ctx.Process(target=timed_spin, args=(q, n)) for _ in range(k)]
        for p in procs:
            p.start()
        times = [q.get() for _ in procs]
        for p in procs:
            p.join()
        return max(times)

    return 2 * run(1) / run(2)


def pair(files, dirname):
    """Two `batch --jobs 1` processes on alternate halves of the files, at once
    (each pinned to its own core: the work shares nothing, hash included)."""
    cmds = [batch(files[half::2], dirname, os.path.join(dirname, f"out{half}"), "--jobs", "1") for half in (0, 1)]
    cmds = [["taskset", "-c", str(half % max(os.cpu_count() or 1, 1))] + c for half, c in enumerate(cmds)]
    t0 = time.perf_counter()
    procs = [subprocess.Popen(c, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL) for c in cmds]
    for p in procs:
        if p.wait() != 0:
            sys.exit(f"enginedyn batch failed (exit {p.returncode}) in the two-process run")
    return (time.perf_counter() - t0) / len(files)


def figures(med, b, stages, samples, file_bytes):
    """The target figures of build `b` (its key prefix) from the medians."""
    compute = statistics.median(g + an for g, an in stages)
    return {
        "x_slow_1": med["slow"] / med[b + "ours1"],
        "x_fast_1": med["fast"] / med[b + "ours1"],
        "x_slow_pin": med["slow"] / med[b + "pin1"],
        "x_fast_pin": med["fast"] / med[b + "pin1"],
        "x_slow_2": med["slow"] / med[b + "ours2"],
        "x_fast_2": med["fast"] / med[b + "ours2"],
        "msamples": samples / max(compute, 1e-9) / 1e6,
        "floor_ratio": med[b + "ours1"] / med[b + "floor"],
        "floor_ratio_pin": med[b + "pin1"] / med[b + "floor"],
        "floor_gbs": file_bytes / med[b + "floor"] / 1e9,
        "scaling": med[b + "ours1"] / med[b + "ours2"],
    }


def same_csv(new, old):
    """'yes', or the columns whose values differ between two summary.csv."""
    if new == old:
        return "yes"
    a = [l.split(",") for l in new.decode().splitlines()]
    b = [l.split(",") for l in old.decode().splitlines()]
    if len(a) != len(b) or a[0] != b[0]:
        return "no (rows or columns differ)"
    cols = sorted({a[0][j] for r, s in zip(a[1:], b[1:]) for j, (x, y) in enumerate(zip(r, s)) if x != y})
    return "no: " + ", ".join(cols)


def callgrind(builds, file, dirname):
    """(whole, parse floor) instructions of one file through each build."""
    out = {}
    for b, exe in builds.items():
        counts = []
        for extra in ((), ("--parse-only",)):
            log = os.path.join(dirname, "callgrind.out")
            cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={log}", exe, "batch", "--engine",
                   os.path.join(dirname, "engine.toml"), "--jobs", "1", "--csv", *extra, file]
            err = subprocess.run(cmd, capture_output=True, text=True).stderr
            counts.append(int(err.split("Collected : ")[1].split()[0]))
        out[b] = tuple(counts)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--files", type=int, default=40)
    ap.add_argument("--cycles", type=int, default=50)
    ap.add_argument("--rounds", type=int, default=9)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--results")
    ap.add_argument("--before", help="a second build, timed in the same rounds")
    ap.add_argument("--callgrind", action="store_true", help="instructions of one file (valgrind)")
    a = ap.parse_args()
    try:
        import numpy, pandas, pyarrow  # noqa: F401
    except ImportError:
        sh([sys.executable, "-m", "pip", "install", "--quiet", "numpy", "pandas", "pyarrow"])
    sh(["cargo", "build", "--release", "--quiet", "-p", "enginedyn"])
    cores = os.cpu_count() or 1
    builds = {"": BIN} | ({"before ": os.path.abspath(a.before)} if a.before else {})
    with tempfile.TemporaryDirectory() as d:
        sh([sys.executable, os.path.join(SHARED, "make_batch.py"), d, "--files", str(a.files),
            "--cycles", str(a.cycles), "--step", "0.1"])
        files = sorted(os.path.join(d, f) for f in os.listdir(d) if f.endswith(".csv"))
        size = sum(os.path.getsize(f) for f in files)
        warm(files + list(builds.values()))
        with open(os.path.join(d, "engine.toml"), "rb") as f:
            z = tomllib.load(f)["cylinders"]
        samples = z * 7200  # 720° at 0.1°
        runs = {"slow": [], "fast": [], "pair": []}
        stages = {b: [] for b in builds}  # (grid, analysis) s per file, inside each --jobs 1 run
        diffs = {b: [] for b in builds}
        csvs = {}
        identical = True
        disk = 0
        probes = []
        for _ in range(a.rounds):
            warm(files)
            runs["slow"].append(yardstick("yardstick.py", files))
            runs["fast"].append(yardstick("yardstick_fast.py", files))
            for r in range(a.repeat):
                for b, exe in builds.items():
                    warm(files + [exe])
                    before = disk_kb()
                    # Full and floor back to back, alternating which goes first.
                    if r % 2 == 0:
                        t1, csv1, st = ours(files, d, "--jobs", "1", "--stage-times", exe=exe)
                        tf, _, _ = ours(files, d, "--jobs", "1", "--parse-only", exe=exe)
                    else:
                        tf, _, _ = ours(files, d, "--jobs", "1", "--parse-only", exe=exe)
                        t1, csv1, st = ours(files, d, "--jobs", "1", "--stage-times", exe=exe)
                    t2, csv2, _ = ours(files, d, "--jobs", "2", "--stage-times", exe=exe)
                    tp, _, _ = ours(files, d, "--jobs", "1", exe=exe, pin=True)
                    disk += disk_kb() - before
                    stages[b].append(st)
                    identical &= csv1 == csv2
                    csvs[b] = csv1
                    for k, v in (("ours1", t1), ("ours2", t2), ("floor", tf), ("pin1", tp)):
                        runs.setdefault(b + k, []).append(v)
                    diffs[b].append(t1 - tf)
                runs["pair"].append(pair(files, d))
                probes.append(cpu_probe())
        instructions = callgrind(builds, files[0], d) if a.callgrind else None
    med = {k: statistics.median(v) for k, v in runs.items()}
    got = {b: figures(med, b, stages[b], samples, size / len(files)) for b in builds}
    lines = [
        f"machine: {cores} cores, {platform.machine()}, {platform.processor() or platform.platform()}; "
        f"python {platform.python_version()}",
        f"batch: {len(files)} files x {a.cycles} cycles at 0.1° ({size / 1e6:.0f} MB), "
        f"{z} cylinders, {a.rounds} interleaved rounds (enginedyn {a.repeat} times in each), medians; "
        f"read from disk during the timed enginedyn runs: {disk / 1024:.1f} MB",
    ]
    if a.before:
        lines.append(f"builds: {BIN} (new) and {builds['before ']} (before), alternating in every round")
    lines += ["", "| program | median s per file | every run (s per file) |", "| --- | --- | --- |"]
    names = {
        "slow": "yardstick.py (pandas)",
        "fast": "yardstick_fast.py (pyarrow, threads)",
    }
    for b in builds:
        names |= {
            b + "ours1": f"{b}enginedyn batch --jobs 1 (the read and the hash beside on the idle core)",
            b + "pin1": f"{b}enginedyn batch --jobs 1, pinned to one core (taskset -c 0)",
            b + "ours2": f"{b}enginedyn batch --jobs 2",
            b + "floor": f"{b}enginedyn batch --jobs 1 --parse-only (parse floor)",
        }
    names["pair"] = "two enginedyn batch --jobs 1 processes at once, half the files each, a core each"
    for k, n in names.items():
        lines.append(f"| {n} | {med[k]:.4f} | {' '.join(f'{v:.4f}' for v in runs[k])} |")
    for b in builds:
        st = stages[b]
        lines.append(f"| {b}compute after parsing, --jobs 1, measured inside the run (grid + analysis) | "
                     f"{statistics.median(g + an for g, an in st):.5f} | {' '.join(f'{g + an:.5f}' for g, an in st)} |")
        lines.append(f"| {b}of which the grid (traces onto the grid, checks, per-cycle combustion, averages) | "
                     f"{statistics.median(g for g, _ in st):.5f} | {' '.join(f'{g:.5f}' for g, _ in st)} |")
        lines.append(f"| {b}of which the analysis (forces, torque, flywheel, summary row) | "
                     f"{statistics.median(an for _, an in st):.5f} | {' '.join(f'{an:.5f}' for _, an in st)} |")
    head = "| target | wanted | measured |" + (" before |" if a.before else "") + " met |"
    lines += ["", head, "| --- " * (head.count("|") - 1) + "|"]
    for label, key, want in TARGETS:
        lower = key in LOWER
        ok = got[""][key] <= want if lower else got[""][key] >= want
        was = f" {got['before '][key]:.2f} |" if a.before else ""
        lines.append(f"| {label} | {'≤' if lower else '≥'} {want} | {got[''][key]:.2f} |{was} {'yes' if ok else 'no'} |")
    lines.append(f"| serial and parallel summary.csv identical | yes | {'yes' if identical else 'no'} |"
                 + (" |" if a.before else "") + f" {'yes' if identical else 'no'} |")
    if a.before:
        lines.append(f"| summary.csv of the two builds | identical | {same_csv(csvs[''], csvs['before '])} | | |")
    machine = med["ours1"] / med["pair"]
    lines += [
        "",
        f"For comparison, the machine's two-core speed-up on the same work (--jobs 1 over two independent "
        f"processes at once): {machine:.2f}; --jobs 2 reaches {got['']['scaling'] / machine:.2f} of it.",
        f"Compute after parsing from the whole-process difference instead: "
        f"{samples / max(statistics.median(diffs['']), 1e-9) / 1e6:.1f} M cylinder-samples/s "
        "(a small difference of two noisy times).",
        f"The machine's two-core speed-up on a pure-Python loop that shares nothing (two processes at once "
        f"against one alone): median {statistics.median(probes):.2f}, every run "
        f"{' '.join(f'{v:.2f}' for v in probes)}.",
    ]
    if instructions:
        lines += ["", "Instructions (callgrind, one file, start-up included):", "",
                  "| build | whole batch | parse floor | whole / floor |", "| --- | --- | --- | --- |"]
        for b, (whole, floor) in instructions.items():
            lines.append(f"| {b or 'new '}| {whole / 1e6:.1f} M | {floor / 1e6:.1f} M | {whole / floor:.3f} |")
    report = "\n".join(lines)
    print(report)
    if a.results:
        with open(a.results, "w") as f:
            f.write(report + "\n")
    if not identical:
        sys.exit("serial and parallel summary.csv differ")


if __name__ == "__main__":
    main()
