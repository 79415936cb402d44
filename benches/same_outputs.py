#!/usr/bin/env python3
"""Two builds of enginedyn, the same outputs (issue 42's "outputs are
identical before and after").

usage: benches/same_outputs.py OLD_BIN NEW_BIN [--rel 0] [--keep DIR]
       (from the repository root; `--parquet` cases need a python with
       pyarrow, else they are skipped and said so)

Cases, each run by both binaries:
- `run --json` and `run` (the printed tables) on every engine of data/,
  with the default options, `--wall-heat woschni`, `--knock`, `--gamma
  brunt`, `--smooth off`;
- `run --json` on every measured-like fixture of tests/fixtures/measured
  with its own flags (expected.json), errors included;
- `batch --csv` and `batch --json --out` on three bench files of
  ../shared/bench/make_batch.py (50 cycles at 0.1°), default and `--knock`;
- `batch --parquet DIR` on the same files: each table read back
  (pyarrow) and compared row by row; the parts' bytes are not compared
  (they hold the writer's version).

stdout, stderr and the exit code must be the same bytes; with `--rel R`,
JSON numbers may differ by R relative (say why in RESULTS.md) and such
differences are listed by key. Prints one line a case and a summary; exit 1
on any difference.
"""
import argparse
import csv
import glob
import json
import math
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = os.path.join(ROOT, "..", "shared", "bench")


def run(exe, args, cwd):
    """Exit code, stdout and stderr, the log's elapsed time taken out."""
    p = subprocess.run([exe, *args], capture_output=True, cwd=cwd)
    return p.returncode, p.stdout, re.sub(rb" in [0-9.]+ s;", b" in (time) s;", p.stderr)


def numbers_apart(a, b, rel, path=""):
    """Keys whose numbers differ by more than `rel` (or differ in kind)."""
    if isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            return [f"{path}: keys"]
        return [k for key in a for k in numbers_apart(a[key], b[key], rel, f"{path}.{key}")]
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: length"]
        return [k for i, (x, y) in enumerate(zip(a, b)) for k in numbers_apart(x, y, rel, f"{path}[{i}]")]
    if isinstance(a, float) and isinstance(b, (int, float)) or isinstance(b, float) and isinstance(a, int):
        if a == b or math.isnan(a) and math.isnan(b) or abs(a - b) <= rel * max(abs(a), abs(b)):
            return []
        return [f"{path}: {a!r} vs {b!r}"]
    return [] if a == b else [f"{path}: {a!r} vs {b!r}"]


def compare(old, new, rel):
    """'same', 'within R' with the keys, or 'differs' with why."""
    if old == new:
        return "same", []
    (rc0, out0, err0), (rc1, out1, err1) = old, new
    if rc0 != rc1 or err0 != err1 or rel == 0:
        return "differs", [f"exit {rc0} vs {rc1}" if rc0 != rc1 else "stderr" if err0 != err1 else "stdout"]
    try:
        a, b = json.loads(out0), json.loads(out1)
    except ValueError:
        a, b = cells(out0), cells(out1)
    apart = numbers_apart(a, b, rel)
    return ("differs", apart) if apart else ("within", numbers_apart(a, b, 0.0))


def cells(text):
    """A CSV's cells, numbers as floats: {column: [values]} under its header."""
    rows = [r for r in csv.reader(text.decode().splitlines()) if r]
    if not rows:
        return {}

    def value(c):
        try:
            return float(c)
        except ValueError:
            return c

    return {h: [value(r[k]) if k < len(r) else None for r in rows[1:]] for k, h in enumerate(rows[0])}


def tables(folder):
    """Each Parquet table under `folder` as (columns, rows) (None without pyarrow)."""
    try:
        import pyarrow.parquet as pq
    except ImportError:
        return None
    out = {}
    for f in sorted(glob.glob(os.path.join(folder, "**", "*.parquet"), recursive=True)):
        t = pq.read_table(f)
        # In the order written (`--jobs 1`: the same order from both builds).
        out[os.path.relpath(f, folder)] = (t.column_names, t.to_pylist())
    return out


def file_verdict(x, y, rel):
    """A written file of both builds (bytes, or a table's columns and rows)."""
    if isinstance(x, bytes):
        return compare((0, x, b""), (0, y, b""), rel)
    if x[0] != y[0] or len(x[1]) != len(y[1]):
        return "differs", ["columns or rows"]
    if not numbers_apart(x[1], y[1], 0.0):
        return "same", []
    return ("within", ["rows"]) if rel and not numbers_apart(x[1], y[1], rel) else ("differs", ["rows"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--rel", type=float, default=0.0)
    ap.add_argument("--keep")
    a = ap.parse_args()
    bins = [os.path.abspath(a.old), os.path.abspath(a.new)]
    work = a.keep or tempfile.mkdtemp(prefix="same_")
    os.makedirs(work, exist_ok=True)
    subprocess.run([sys.executable, os.path.join(SHARED, "make_batch.py"), work, "--files", "3", "--cycles", "50",
                    "--step", "0.1"], check=True, capture_output=True)
    files = sorted(glob.glob(os.path.join(work, "d*.csv")))
    engine = os.path.join(work, "engine.toml")
    cases = []
    for toml in sorted(glob.glob(os.path.join(ROOT, "data", "*.toml"))):
        name = os.path.basename(toml)
        for opts in ([], ["--wall-heat", "woschni"], ["--knock"], ["--gamma", "brunt"], ["--smooth", "off"]):
            cases.append((f"run {name} {' '.join(opts)}", ["run", "--engine", toml, *opts, "--json"]))
        cases.append((f"run {name} (tables)", ["run", "--engine", toml]))
    with open(os.path.join(ROOT, "tests", "fixtures", "measured", "expected.json")) as f:
        expected = json.load(f)
    for fx in expected["fixtures"]:
        cases.append((f"fixture {fx['id']}", ["run", "--engine", os.path.join(ROOT, "data", "single.toml"),
                                              "--diagram", os.path.join(ROOT, fx["file"]), *fx["flags"], "--json"]))
    for opts in ([], ["--knock"]):
        cases.append((f"batch --csv {' '.join(opts)}", ["batch", "--engine", engine, "--jobs", "1", "--csv", *opts, *files]))
    counts = {"same": 0, "within": 0, "differs": 0}
    for label, args in cases:
        got = [run(b, args, ROOT) for b in bins]
        verdict, why = compare(*got, a.rel)
        counts[verdict] += 1
        print(f"{verdict:8} {label}" + (f": {'; '.join(why[:6])}" + (" …" if len(why) > 6 else "") if why else ""))
    # Folders: summary.json of each file, and the campaign's tables.
    for label, extra in (("batch --json --out", ["--json"]), ("batch --parquet", ["--parquet"])):
        outs = []
        for b in bins:
            # The same folder for both builds: messages name it.
            out = os.path.join(work, "out")
            subprocess.run(["rm", "-rf", out])
            args = ["batch", "--engine", engine, "--jobs", "1", *files]
            args += ["--out", out] if extra == ["--json"] else ["--csv", "--parquet", out]
            rc, stdout, err = run(b, args, ROOT)
            if extra == ["--json"]:
                found = {os.path.relpath(f, out): open(f, "rb").read()
                         for f in sorted(glob.glob(os.path.join(out, "**", "*.csv"), recursive=True))}
                found["stdout"] = stdout
            else:
                found = tables(out)
            outs.append((rc, err, found))
        if outs[0][2] is None:
            print(f"skipped  {label}: no pyarrow in this python")
            continue
        verdict, why = "same", []
        if outs[0][0] != 0 or outs[0][:2] != outs[1][:2] or outs[0][2].keys() != outs[1][2].keys():
            verdict, why = "differs", ["exit, log or files"]
        else:
            rank = {"same": 0, "within": 1, "differs": 2}
            for name in outs[0][2]:
                v, w = file_verdict(outs[0][2][name], outs[1][2][name], a.rel)
                if rank[v] > rank[verdict]:
                    verdict, why = v, [f"{name}: {x}" for x in w]
        counts[verdict] += 1
        print(f"{verdict:8} {label} ({len(outs[0][2])} files)" + (f": {'; '.join(why[:6])}" if why else ""))
    print(f"{len(cases) + 2} cases: {counts['same']} the same bytes, {counts['within']} within {a.rel:g} relative, "
          f"{counts['differs']} differ")
    sys.exit(1 if counts["differs"] else 0)


if __name__ == "__main__":
    main()
