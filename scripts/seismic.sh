#!/usr/bin/env bash
# Regenerates results/seismic/: configs/seismic.toml (a structure in a Kanai-Tajimi ground
# motion's band, 16 designs over m and d, five intensities S0, 1,000 realizations each: 80,000
# runs) run and reduced by scripts/showcase.sh, its report.html beside the report. The designs
# are ranked at the design intensity by subset simulation where Monte Carlo saw fewer than 10
# exceedances. A release build takes about 25 s on 2 cores. tests/reproduce.rs checks the
# committed files byte for byte.
#
#   scripts/seismic.sh [WORK_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
DEST=${DEST:-results/seismic}
if [ $# -ge 1 ]; then
    WORK=$1
    mkdir -p "$WORK"
else
    WORK=$(mktemp -d)
    trap 'rm -rf "$WORK"' EXIT
fi
DEST=$DEST scripts/showcase.sh configs/seismic.toml results/seismic "$WORK"
cp "$WORK"/seismic/report.html "$DEST"/
