#!/usr/bin/env bash
# The capacities' peer (issue 67): impactsweep and OpenSeesPy, incremental dynamic analysis of one
# record and one design (scripts/peer_random.py's), one script run, writing results/peer_ida.md
# and results/peer_ida.json.
#
# Sets up .venv-peers as scripts/peer_random.sh does (openseespy, numpy, scipy, pyarrow). Pass
# --bin PATH to use a given binary (default target/release/impactsweep, built here if missing),
# --grid quick for one step per contact stiffness instead of peer_random's whole grid.
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
exec .venv-peers/bin/python scripts/peer_ida.py "$@"
