#!/usr/bin/env bash
# Regenerates results/design-map/: configs/design-map.toml (harmonic forcing; five clearances,
# each over 31 frequency ratios, a 16-start census per run: 155 runs) run and reduced by
# scripts/showcase.sh, with its bifurcation curves over d (bifurcations.csv) and the forced
# design map (design_map.png). About 11 s on 2 cores with a release build, run and reduce with
# its verification (20 s of CPU; stop 87, idle Intel Xeon).
# tests/reproduce.rs checks the committed files byte for byte.
#
#   scripts/design_map.sh [WORK_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
exec scripts/showcase.sh configs/design-map.toml results/design-map "$@"
