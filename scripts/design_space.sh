#!/usr/bin/env bash
# Regenerates results/design-space/: configs/design-space.toml (e x m x d, 3,146 design points x
# 9 cases) run and reduced by scripts/showcase.sh; the report, every chart (SVG + PNG, each with
# its data as CSV) and the summary, zones, jumps and sensitivity tables as CSV. The run is
# deterministic, so a re-run rewrites the committed files byte for byte (tests/reproduce.rs
# checks it).
#
#   scripts/design_space.sh [WORK_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
exec scripts/showcase.sh configs/design-space.toml results/design-space "$@"
