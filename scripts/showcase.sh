#!/usr/bin/env bash
# Runs and reduces a bundled study and copies its reduction into a results directory: the
# report, every chart (SVG + PNG, each with its data as CSV) and the summary, zones, jumps and
# sensitivity tables as CSV. The showcase scripts call it (scripts/reproduce_paper.sh, scripts/design_space.sh,
# scripts/frequency_response.sh).
#
#   scripts/showcase.sh STUDY DEST [WORK_DIR]
#
# WORK_DIR holds the dataset (default: a fresh temporary directory, removed afterwards). The
# run is deterministic (seeded noise, seeded bootstrap, no timestamps in any written file), so a
# re-run rewrites DEST byte for byte. DEST may be overridden by the environment (the test that
# checks the committed files regenerates into a temporary DEST), and IMPACTSWEEP_BIN names the
# binary to use (default: a release build).
set -euo pipefail

cd "$(dirname "$0")/.."
ROOT=$(pwd)
STUDY=$1
DEST=${DEST:-$2}

if [ $# -ge 3 ]; then
    WORK=$3
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

# The study's [study].name names the run directory OUT/<name>.
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
