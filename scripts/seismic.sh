#!/usr/bin/env bash
# Regenerates results/seismic/: configs/seismic.toml (a structure in a Clough-Penzien ground
# motion's band, 16 designs over m and d, six stripes of Sa(T1) in g, 1,000 realizations each,
# capacities by incremental dynamic analysis at the design stripe, designs ranked by annual risk
# over an illustrative hazard curve) run and reduced by scripts/showcase.sh, its report.html
# beside the report. About 19 s on 2 cores (36 s of CPU, dev-profile build; stop 87).
# tests/reproduce.rs checks the committed files byte for byte (an ignored test; CI reruns one
# design's slice). The record-suite sibling: scripts/seismic_records.sh.
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
