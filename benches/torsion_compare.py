#!/usr/bin/env python3
"""openTorsion (pip install opentorsion, MIT) against enginedyn on one chain.

    pip install opentorsion
    python3 benches/torsion_compare.py [data/i6_diesel.toml]

Runs `enginedyn torsion --out TMP --chain` (the hidden flag writes
chain.json: the chain, and forced responses at four speeds and several
orders), builds the same chain in openTorsion (Disk and Shaft elements,
its modal damping `C_modal` plus the damper's viscous coefficient across
its spring) and compares the natural frequencies (1e-6 relative) and the
complex responses (1e-3 relative to each response's largest amplitude).
Exit 1 on a miss.
"""
import json, subprocess, sys, tempfile, time
from pathlib import Path

import numpy as np
import opentorsion as ot

root = Path(__file__).resolve().parent.parent
engine = sys.argv[1] if len(sys.argv) > 1 else str(root / "data/i6_diesel.toml")
exe = root / "target/release/enginedyn"
if not exe.exists():
    exe = root / "target/debug/enginedyn"
with tempfile.TemporaryDirectory() as tmp:
    t0 = time.perf_counter()
    subprocess.run([str(exe), "torsion", "--engine", engine, "--out", tmp, "--chain"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    t_rust = time.perf_counter() - t0
    chain = json.loads(Path(tmp, "chain.json").read_text())

J = chain["inertia_kg_m2"]
k = chain["stiffness_nm_rad"]
cs = chain["spring_damping_nm_s_rad"]
t0 = time.perf_counter()
shafts = [ot.Shaft(i, i + 1, k=k[i], I=0.0, c=cs[i]) for i in range(len(k))]
disks = [ot.Disk(i, I=J[i]) for i in range(len(J))]
asm = ot.Assembly(shafts, disk_elements=disks)
lam, _ = asm.undamped_modal_analysis()
f_ot = np.sort(np.sqrt(np.abs(lam.real))) / (2 * np.pi)
C = asm.C_modal(asm.M, asm.K, xi=chain["damping_ratio"]) + asm.C
worst_f = 0.0
for a, b in zip(f_ot[1:], chain["natural_frequencies_hz"]):
    worst_f = max(worst_f, abs(a - b) / b)
worst_r = 0.0
for c in chain["checks"]:
    T = np.array([complex(*x) for x in c["torque"]])
    q, _ = asm.ss_response(T.reshape(-1, 1), np.array([c["omega_rad_s"]]), C=C)
    ours = np.array([complex(*x) for x in c["response"]])
    # Relative to the largest amplitude; the rigid rotation included.
    worst_r = max(worst_r, np.max(np.abs(q[:, 0] - ours)) / np.max(np.abs(q[:, 0])))
t_ot = time.perf_counter() - t0
print(f"natural frequencies: largest relative difference {worst_f:.2e} (bound 1e-6)")
print(f"forced response ({len(chain['checks'])} speed-order pairs): largest relative difference {worst_r:.2e} (bound 1e-3)")
print(f"enginedyn torsion (whole command, {exe.parent.name}): {t_rust*1e3:.0f} ms; openTorsion on the checks alone: {t_ot*1e3:.0f} ms")
sys.exit(0 if worst_f < 1e-6 and worst_r < 1e-3 else 1)
