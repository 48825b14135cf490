#!/usr/bin/env bash
# The Python package's speed (issue 17): builds the release binary and installs the package into
# .venv, then runs scripts/bench_python.py once and prints its Markdown table (BENCHMARKS.md,
# "Python package"). A measurement, never a test.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup-python.sh
cargo build --release --quiet
# maturin (pinned in .venv) builds it; the venv on PATH is where its pip hook finds the binary.
PATH="$PWD/.venv/bin:$PATH" .venv/bin/pip install --quiet --disable-pip-version-check --no-build-isolation ./python
.venv/bin/python scripts/bench_python.py --bin target/release/impactsweep "$@"
