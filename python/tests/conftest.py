"""Shared fixtures: the command-line binary the package is compared with, and the repository."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _binary() -> Path:
    """`$IMPACTSWEEP_BIN`, else the newest build in `target/`, else a release build made now."""
    env = os.environ.get("IMPACTSWEEP_BIN")
    if env:
        return Path(env)
    built = [p for p in (ROOT / "target/release/impactsweep", ROOT / "target/debug/impactsweep") if p.exists()]
    if built:
        return max(built, key=lambda p: p.stat().st_mtime)
    subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    return ROOT / "target/release/impactsweep"


@pytest.fixture(scope="session")
def cli():
    """Runs the command line: `cli(*args, cwd=None)` -> CompletedProcess (text, not checked)."""
    exe = _binary()

    def call(*args, cwd=None):
        return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, cwd=cwd)

    return call


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT
