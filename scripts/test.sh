#!/usr/bin/env bash
# The whole test suite, from a fresh clone: installs what the tests need (pinned Python packages
# for the interop tests), checks formatting and lints, then runs every test: the Rust suite, then
# the Python package (python/) built and installed into .venv the way a user does
# (`pip install ./python`) and its pytest suite, compared against the binary just tested.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup-python.sh
export IMPACTSWEEP_PYTHON="$PWD/.venv/bin/python"
cargo fmt --check
cargo clippy --all-targets -- -D warnings
cargo test --all-targets
cargo fmt --check --manifest-path python/Cargo.toml
cargo clippy --manifest-path python/Cargo.toml --all-targets -- -D warnings
# maturin (pinned in .venv) builds it; the venv on PATH is where its pip hook finds the binary.
PATH="$PWD/.venv/bin:$PATH" .venv/bin/pip install --quiet --disable-pip-version-check --no-build-isolation ./python
IMPACTSWEEP_BIN="$PWD/target/debug/impactsweep" .venv/bin/python -m pytest python/tests -q
