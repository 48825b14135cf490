#!/usr/bin/env bash
# Reproduces Afsharfard & Kolahan (2013) with impactsweep and regenerates results/afsharfard2013/:
# the report, charts (SVG + PNG, each with its data as CSV), summary/zones/jumps/sensitivity as
# CSV, the waveform figures and paper-comparison.md (the paper's numbers beside ours).
#
#   scripts/reproduce_paper.sh [WORK_DIR]
#
# WORK_DIR holds the dataset (default: a fresh temporary directory, removed afterwards). The
# run is deterministic (seeded noise, seeded bootstrap, no timestamps in any written file), so a
# re-run rewrites the committed files byte for byte; `git status results/` shows any drift.
set -euo pipefail

cd "$(dirname "$0")/.."
ROOT=$(pwd)
STUDY=configs/paper.toml
# DEST and IMPACTSWEEP_BIN may be set by the test that checks the committed files
# (tests/reproduce.rs): it regenerates into a temporary DEST with the test build's binary.
DEST=${DEST:-results/afsharfard2013}

if [ $# -ge 1 ]; then
    WORK=$1
    mkdir -p "$WORK"
else
    WORK=$(mktemp -d)
    trap 'rm -rf "$WORK"' EXIT
fi

# The study run and reduced, its reduction copied into DEST (scripts/showcase.sh, which builds
# the release binary unless IMPACTSWEEP_BIN names one).
DEST="$DEST" scripts/showcase.sh "$STUDY" "$DEST" "$WORK" > /dev/null
BIN=${IMPACTSWEEP_BIN:-$ROOT/target/release/impactsweep}

# The paper's Figures 2 and 5: with/without damper, e = 0.45 against e = 0.9.
"$BIN" plot waveform --out "$DEST" --e 0.45 0.9 --t-end 0.5 > /dev/null

# The system without damper, for the comparison of first peaks.
"$BIN" simulate --set m=0 --json > "$WORK/no_damper.json"

"${IMPACTSWEEP_PYTHON:-python3}" scripts/paper_comparison.py "$DEST" "$WORK/no_damper.json" "$STUDY" > "$DEST/paper-comparison.md"

echo "wrote $DEST:"
ls "$DEST"
