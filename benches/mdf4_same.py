#!/usr/bin/env python3
"""Two builds of enginedyn on the same MDF4 files: byte-identical outputs.

usage: benches/mdf4_same.py OLD_BIN NEW_BIN [--keep DIR]
       (with a python that has numpy and asammdf)

The files: the repository's MDF4 fixtures (tests/fixtures/measured), the
bench file of benches/mdf4.py, and files written here to reach every path of
the reader: each data/ engine's diagram as an angle master and a pressure
(float64, and int16 through a linear conversion), compressed (##DZ) and not;
six pressure channels side by side (one cycle per column) with a `Cycle`
counter; a pressure with invalid samples (invalidation bits); the records
cut short; the records in two data blocks under a data list; the records
unsorted (a record id before each); a four-cylinder time record with a TDC
pulse. Each is read by `run` (text and `--json`) and `batch --csv` (and
`--parse-only`), by both binaries; stdout, stderr and the exit code
must be the same bytes. Prints one line a case and a summary; exit 1 on any
difference.
"""
import argparse
import os
import struct
import subprocess
import sys
import tempfile

import numpy as np
from asammdf import MDF, Signal

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
FIX = os.path.join(ROOT, "tests", "fixtures", "measured")
DATA = os.path.join(ROOT, "data")
SHARED = "/work/shared/bench" if os.path.isdir("/work/shared/bench") else os.path.join(ROOT, "..", "shared", "bench")


def rows(path):
    lines = [r for r in open(path).read().splitlines() if r and not r.startswith("#")]
    head = lines[0].split(",")
    return head, np.array([r.split(",") for r in lines[1:]], dtype=float)


def save(m, path, compression=0):
    m.save(path, overwrite=True, compression=compression)
    m.close()
    return path


def angle_file(path, a, p, *, dtype=np.float64, conv=None, invalid=None, compression=0, extra=()):
    m = MDF(version="4.10")
    sig = Signal(
        p.astype(dtype),
        a,
        name="PCYL1",
        unit="bar",
        master_metadata=("Crank angle", 2),
        conversion=conv,
        invalidation_bits=invalid,
    )
    m.append([sig, *extra], acq_name="Indicating")
    return save(m, path, compression)


def blocks(b):
    """(u64 reader, link reader) over a file's bytes."""
    u64 = lambda at: struct.unpack_from("<Q", b, at)[0]
    link = lambda at, i: u64(at + 24 + 8 * i)
    return u64, link


def append(b, ident, links, data):
    while len(b) % 8:
        b.append(0)
    at = len(b)
    b += b"##" + ident[2:] + bytes(4) + struct.pack("<QQ", 24 + 8 * len(links) + len(data), len(links))
    for l in links:
        b += struct.pack("<Q", l)
    b += data
    return at


def edited(src, dst, how):
    """The single-group angle file `src` edited: its records `cut` short,
    split under a data `list`, or `unsorted` (a 1-byte record id)."""
    b = bytearray(open(src, "rb").read())
    u64, link = blocks(b)
    dg = link(64, 0)
    cg = link(dg, 1)
    dt = link(dg, 2)
    assert b[dt:dt + 4] == b"##DT", b[dt:dt + 4]
    n = u64(dt + 8) - 24
    cg_data = cg + 24 + 8 * u64(cg + 16)
    count = u64(cg_data + 8)
    rec = n // count
    if how == "cut":
        struct.pack_into("<Q", b, dt + 8, 24 + (count * 2 // 3) * rec + rec // 2)
    elif how == "list":
        half = (count // 2) * rec
        tail = bytes(b[dt + 24 + half:dt + 24 + n])
        struct.pack_into("<Q", b, dt + 8, 24 + half)
        dt2 = append(b, b"##DT", [], tail)
        d = struct.pack("<BxxxI", 0, 2) + struct.pack("<QQ", 0, half)
        dl = append(b, b"##DL", [0, dt, dt2], d)
        struct.pack_into("<Q", b, dg + 24 + 16, dl)
    elif how == "unsorted":
        b[dg + 24 + 8 * u64(dg + 16)] = 1
        cg2 = append(b, b"##CG", [0] * 6, struct.pack("<QQ", 2, 0) + bytes(16))
        struct.pack_into("<Q", b, cg + 24, cg2)
        recs = bytes(b[dt + 24:dt + 24 + n])
        d = bytearray()
        for k in range(count):
            d.append(1)
            d += recs[k * rec:(k + 1) * rec]
        dt2 = append(b, b"##DT", [], bytes(d))
        struct.pack_into("<Q", b, dg + 24 + 16, dt2)
    open(dst, "wb").write(b)
    return dst


def corpus(d):
    """[(name, path, engine, flags)]."""
    single = os.path.join(DATA, "single.toml")
    out = [
        ("fixture angle master", os.path.join(FIX, "mdf_angle_master.mf4"), single, []),
        ("fixture angle master --group 2", os.path.join(FIX, "mdf_angle_master.mf4"), single, ["--group", "2"]),
        ("fixture time master dz", os.path.join(FIX, "mdf_time_master_dz.mf4"), single, ["--gain", "20", "--peg-bar", "0.95"]),
        ("fixture time master dz --group 1", os.path.join(FIX, "mdf_time_master_dz.mf4"), single, ["--group", "1", "--gain", "20", "--peg-bar", "0.95"]),
        ("fixture no pressure", os.path.join(FIX, "mdf_no_pressure.mf4"), single, []),
    ]
    # benches/mdf4.py's file: the bench inline-6, 20 cycles, the angle running on.
    subprocess.run([sys.executable, os.path.join(SHARED, "make_batch.py"), d, "--files", "1", "--cycles", "20"], check=True, capture_output=True)
    src = next(os.path.join(d, f) for f in sorted(os.listdir(d)) if f.endswith(".csv"))
    head, data = rows(src)
    p = data[:, head.index("pressure_bar")]
    a = np.arange(len(p)) / 10.0
    out.append(("bench run on", angle_file(os.path.join(d, "run_on.mf4"), a, p), os.path.join(d, "engine.toml"), []))
    for f in sorted(os.listdir(DATA)):
        if not f.endswith(".csv"):
            continue
        eng = os.path.join(DATA, f[:-4] + ".toml")
        head, data = rows(os.path.join(DATA, f))
        a, p = data[:, 0], data[:, 1]
        base = os.path.join(d, f[:-4])
        out.append((f"{f} float64", angle_file(base + ".mf4", a, p), eng, []))
        if f == "single.csv":
            lo, hi = p.min(), p.max()
            scale = (hi - lo) / 60000
            raw = np.round((p - lo) / scale - 30000)
            conv = {"a": scale, "b": lo + 30000 * scale}
            out.append((f"{f} int16 linear dz", angle_file(base + "_i16.mf4", a, raw, dtype=np.int16, conv=conv, compression=2), eng, []))
            bad = np.zeros(len(p), bool)
            bad[len(p) // 3] = True
            out.append((f"{f} invalid sample", angle_file(base + "_inv.mf4", a, p, invalid=bad), eng, []))
            whole = angle_file(base + "_whole.mf4", np.concatenate([a, a + 720]), np.concatenate([p, p * 1.01]))
            for how in ("cut", "list", "unsorted"):
                out.append((f"{f} {how}", edited(whole, base + f"_{how}.mf4", how), eng, []))
    # Six pressures side by side, a cycle counter: one cycle per column.
    head, data = rows(os.path.join(DATA, "i6_diesel.csv"))
    a, p = data[:, 0], data[:, 1]
    rng = np.random.default_rng(42)
    a2 = np.concatenate([a - 360, a + 360])
    cyc = np.repeat([1, 2], len(a)).astype(np.uint16)
    m = MDF(version="4.10")
    sigs = [Signal(np.concatenate([p, p]) + 0.01 * rng.standard_normal(2 * len(p)), a2, name=f"PCYL{k}", unit="bar", master_metadata=("Crank angle", 2)) for k in range(1, 7)]
    m.append(sigs, acq_name="Six")
    out.append(("six cylinders per column", save(m, os.path.join(d, "six.mf4")), os.path.join(DATA, "i6_diesel.toml"), []))
    # Three cycles side by side (one name), and a cycle counter in a long record.
    m = MDF(version="4.10")
    m.append([Signal(s.samples, a2, name="pressure", unit="bar", master_metadata=("Crank angle", 2)) for s in sigs[:3]], acq_name="Three")
    out.append(("three cycles per column", save(m, os.path.join(d, "three.mf4")), os.path.join(DATA, "single.toml"), []))
    m = MDF(version="4.10")
    m.append([sigs[0], Signal(cyc, a2, name="Cycle", unit="", master_metadata=("Crank angle", 2))], acq_name="Counted")
    out.append(("cycle counter", save(m, os.path.join(d, "counted.mf4")), os.path.join(DATA, "single.toml"), []))
    # A four-cylinder time record with a TDC pulse (tests/python/test_habits.py's shape).
    fs, rpm = 50000.0, 1500.0
    t = np.arange(int(0.4 * fs)) / fs
    phi = (t * rpm * 6.0) % 720.0
    v = [1.0 + 3.0 * np.exp(-(((phi - off) % 720 - 360) / 30.0) ** 2) for off in (0, 540, 180, 360)]
    tdc = np.where((t * rpm * 6.0) % 360.0 < 4.0, 5.0, 0.0)
    m = MDF(version="4.10")
    m.append([Signal(v[k], t, name=f"P_Cyl{k + 1}", unit="V") for k in range(4)] + [Signal(tdc, t, name="TDC", unit="V")])
    out.append(("four-cylinder time record", save(m, os.path.join(d, "four.mf4")), os.path.join(DATA, "vaz2108.toml"), ["--gain", "20", "--peg-bar", "1.0"]))
    return out


def runs(binary, path, engine, flags, d):
    cases = [
        ["run", "--engine", engine, "--diagram", path, "--json", *flags],
        ["run", "--engine", engine, "--diagram", path, *flags],
        ["batch", "--engine", engine, "--csv", "--jobs", "1", *flags, path],
        ["batch", "--engine", engine, "--parse-only", "--jobs", "1", *flags, path],
    ]
    out = []
    for c in cases:
        r = subprocess.run([binary, *c], capture_output=True, cwd=d)
        out.append((" ".join(c[:1] + [x for x in c[1:] if x.startswith("--") and x not in ("--engine", "--diagram")]), r.returncode, r.stdout, r.stderr.replace(path.encode(), b"FILE")))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--keep")
    a = ap.parse_args()
    d = a.keep or tempfile.mkdtemp(prefix="edmdfsame_")
    os.makedirs(d, exist_ok=True)
    bad = 0
    total = 0
    for name, path, engine, flags in corpus(d):
        old = runs(a.old, path, engine, flags, d)
        new = runs(a.new, path, engine, flags, d)
        for (what, rc0, o0, e0), (_, rc1, o1, e1) in zip(old, new):
            total += 1
            same = (rc0, o0, e0) == (rc1, o1, e1)
            bad += not same
            print(f"{'same' if same else 'DIFFERENT'}  exit {rc0}  {len(o0):>8} B  {name}: {what}")
            if not same:
                print(f"    old exit {rc0}: {e0.decode()[:300]}\n    new exit {rc1}: {e1.decode()[:300]}")
    print(f"\n{total - bad} of {total} identical (stdout, stderr, exit code)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
