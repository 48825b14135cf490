#!/usr/bin/env bash
# The record scene's peers (issue 44): impactsweep, OpenSeesPy and SciPy on one accelerogram,
# one script run, writing results/peer_random.md and results/peer_random.json.
#
# Sets up .venv-peers (openseespy, numpy, scipy, pyarrow) if it is missing: a venv of its own,
# because OpenSeesPy is a peer to compare with, not something the project or CI needs. Pass
# --bin PATH to time a given binary (default target/release/impactsweep, built here if missing).
# A measurement, never a test.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x .venv-peers/bin/python ] || ! .venv-peers/bin/python -c "import openseespy, scipy, pyarrow" 2>/dev/null; then
    python3 -m venv .venv-peers
    .venv-peers/bin/pip install --quiet --disable-pip-version-check openseespy numpy scipy pyarrow
fi
bin=target/release/impactsweep
for ((i = 1; i <= $#; i++)); do
    if [ "${!i}" = "--bin" ]; then j=$((i + 1)); bin=${!j}; fi
    case "${!i}" in --bin=*) bin=${!i#--bin=} ;; esac
done
if [ "$bin" = target/release/impactsweep ] && [ ! -x "$bin" ]; then
    cargo build --release --quiet
fi
exec .venv-peers/bin/python scripts/peer_random.py "$@"
