#!/usr/bin/env bash
# Regenerates results/multi-unit/: configs/multi-unit.toml (harmonic forcing; the same added
# mass over 1, 2, 4 and 8 units with equal and spread clearances, 31 frequency ratios, 5 cases:
# 2,480 runs) run and reduced by scripts/showcase.sh. tests/reproduce.rs reruns one design's ideal
# curve (2 units, d_spread = 0.5) as a shard of the study and checks it against the committed files
# bit for bit; the whole regeneration (about 1,040 s of CPU in the release build, 10 minutes on 2
# cores), byte for byte, is an ignored test there.
#
#   scripts/multi_unit.sh [WORK_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
exec scripts/showcase.sh configs/multi-unit.toml results/multi-unit "$@"
