#!/usr/bin/env python3
"""The CLI (crates/cli) and the Python extension (crates/python) must build
their shared dependencies with one set of features: then the release build of
`cargo run --release` serves maturin too, and CI builds the dependencies once.
Prints each package whose features differ and exits 1 (crates/cli/Cargo.toml
asks for the extension's features; add the one named here)."""
import subprocess
import sys


def features(package):
    out = subprocess.run(
        ["cargo", "tree", "-q", "-p", package, "-e", "normal,build",
         "-f", "{p} {f}", "--prefix", "none", "--target", "x86_64-unknown-linux-gnu"],
        check=True, capture_output=True, text=True).stdout
    found = {}
    for line in out.splitlines():
        parts = line.replace(" (*)", "").replace(" (proc-macro)", "").split()
        if len(parts) < 2 or parts[0].startswith("enginedyn"):
            continue
        key = f"{parts[0]} {parts[1]}"
        feats = set(parts[2].split(",")) if len(parts) > 2 and not parts[2].startswith("(") else set()
        found.setdefault(key, set()).update(feats)
    return found


cli, ext = features("enginedyn"), features("enginedyn-python")
bad = [(k, cli[k] ^ ext[k]) for k in sorted(cli.keys() & ext.keys()) if cli[k] != ext[k]]
for key, diff in bad:
    print(f"same_features: {key} differs in {sorted(diff)}")
sys.exit(1 if bad else 0)
