#!/usr/bin/env bash
# Regenerates results/seismic-records/: configs/seismic-records.toml (the seismic showcase's
# structure, limit and hazard under the bundled suite of eleven synthetic records,
# configs/records/suite/, made by scripts/make_suite.py), run and reduced by scripts/showcase.sh,
# its report.html beside the report. About a second of runs. tests/reproduce.rs checks the
# committed files byte for byte.
#
#   scripts/seismic_records.sh [WORK_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
DEST=${DEST:-results/seismic-records}
if [ $# -ge 1 ]; then
    WORK=$1
    mkdir -p "$WORK"
else
    WORK=$(mktemp -d)
    trap 'rm -rf "$WORK"' EXIT
fi
DEST=$DEST scripts/showcase.sh configs/seismic-records.toml results/seismic-records "$WORK"
cp "$WORK"/seismic-records/report.html "$DEST"/
