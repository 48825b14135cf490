#!/usr/bin/env bash
# The whole test suite, from a fresh clone: installs what the tests need (pinned Python packages
# for the interop tests), checks formatting and lints, then runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup-python.sh
export IMPACTSWEEP_PYTHON="$PWD/.venv/bin/python"
cargo fmt --check
cargo clippy --all-targets -- -D warnings
cargo test --all-targets
