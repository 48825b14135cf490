#!/usr/bin/env bash
# Regenerates results/frequency-response/: configs/frequency-response.toml (harmonic forcing;
# 3 inner masses x 3 clearances, each over 81 frequency ratios, 5 cases: 3,645 runs) run and
# reduced by scripts/showcase.sh. A release build takes about 4 s of CPU to run it and 5 s to
# reduce it (most of that locating jumps: each probe simulates a whole curve); 5 s and 5 s of
# wall time on 2 shared cores at load 2.6-3.4. tests/reproduce.rs checks the committed files
# byte for byte.
#
#   scripts/frequency_response.sh [WORK_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
exec scripts/showcase.sh configs/frequency-response.toml results/frequency-response "$@"
