#!/usr/bin/env bash
# Regenerates results/frequency-response/: configs/frequency-response.toml (harmonic forcing;
# 3 inner masses x 3 clearances, each over 81 frequency ratios, 5 cases: 3,645 runs) run and
# reduced by scripts/showcase.sh. With the attractor census (8 starts per run), the design
# lives of its chaotic motions and, in `reduce`, the verification of the best design's motions,
# it ran in about 49 s and reduced in about 24 s of wall time on 2 cores (stop 84, dev-profile
# build; BENCHMARKS.md, "A cheaper simulated period"; results/bench_issue69_budget.md).
# tests/reproduce.rs checks the committed files byte for byte.
#
#   scripts/frequency_response.sh [WORK_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
exec scripts/showcase.sh configs/frequency-response.toml results/frequency-response "$@"
