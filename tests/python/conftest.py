"""Shared fixtures of the Python package's tests: the repository root and
the CLI binary built from the same sources (`cargo build --release`)."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
# Paths in the tests are the repository's, as the CLI is run from its root.
os.chdir(ROOT)


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    return ROOT


@pytest.fixture(scope="session")
def cli() -> str:
    exe = os.environ.get("ENGINEDYN_BIN", str(ROOT / "target" / "release" / "enginedyn"))
    if not os.path.exists(exe):
        subprocess.run(["cargo", "build", "--release", "-q", "-p", "enginedyn"], cwd=ROOT, check=True)
    return exe
