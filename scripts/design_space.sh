#!/usr/bin/env bash
# Regenerates results/design-space/: configs/design-space.toml (e x m x d, 3,146 design points x
# 9 cases) run and reduced; the report, every chart (SVG + PNG, each with its data as CSV) and
# the summary, zones, jumps and sensitivity tables as CSV.
#
#   scripts/design_space.sh [WORK_DIR]
#
# WORK_DIR holds the dataset (default: a fresh temporary directory, removed afterwards). The
# run is deterministic (seeded noise, seeded bootstrap, no timestamps in any written file), so a
# re-run rewrites the committed files byte for byte (tests/reproduce.rs checks it).
set -euo pipefail

cd "$(dirname "$0")/.."
ROOT=$(pwd)
STUDY=configs/design-space.toml
# DEST and IMPACTSWEEP_BIN may be set by the test that checks the committed files.
DEST=${DEST:-results/design-space}

if [ $# -ge 1 ]; then
    WORK=$1
    mkdir -p "$WORK"
else
    WORK=$(mktemp -d)
    trap 'rm -rf "$WORK"' EXIT
fi

if [ -n "${IMPACTSWEEP_BIN:-}" ]; then
    BIN=$IMPACTSWEEP_BIN
else
    cargo build --release --quiet
    BIN=$ROOT/target/release/impactsweep
fi

NAME=$(sed -n 's/^name *= *"\([^"]*\)".*/\1/p' "$STUDY" | head -n 1)
RUN=$WORK/$NAME
rm -rf "$RUN"

"$BIN" run "$STUDY" --out "$WORK" --quiet
"$BIN" reduce "$RUN" > /dev/null

rm -rf "$DEST"
mkdir -p "$DEST"
cp "$RUN"/report.md "$RUN"/*.csv "$RUN"/*.svg "$RUN"/*.png "$DEST"/

echo "wrote $DEST:"
ls "$DEST"
