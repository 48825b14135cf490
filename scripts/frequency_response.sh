#!/usr/bin/env bash
# Regenerates results/frequency-response/: configs/frequency-response.toml (harmonic forcing;
# 3 inner masses x 3 clearances, each over 81 frequency ratios, 5 cases: 3,645 runs) run and
# reduced by scripts/showcase.sh. About 3 s to run and 3 s to reduce on 2 cores (release
# build); tests/reproduce.rs checks the committed files byte for byte.
#
#   scripts/frequency_response.sh [WORK_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
exec scripts/showcase.sh configs/frequency-response.toml results/frequency-response "$@"
