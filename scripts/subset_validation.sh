#!/usr/bin/env bash
# Subset simulation against exact and Monte Carlo answers (issue 67, item 5):
# results/subset_validation.md and its data in results/subset_validation/.
#
#   scripts/subset_validation.sh          the exact case (150 runs at P = 1e-3, 1e-5, 1e-8; the report
#                                         shows the first 50 and all) and 30
#                                         runs of each seismic design (a few minutes on 2 cores),
#                                         then the report
#   scripts/subset_validation.sh --mc [N] Monte Carlo of both designs first, N realizations each
#                                         (10^6 by default: about 5 CPU-minutes per design)
#   scripts/subset_validation.sh --report the report alone, from the committed files
#   scripts/subset_validation.sh --check  what CI runs: the report regenerates byte for byte from
#                                         the committed runs, and a slice is reproduced bit for bit
#                                         (3 runs of the exact case at 1e-3 and run 0 of design A:
#                                         a few seconds)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=results/subset_validation
# SUBSET_VALIDATION_BIN: an example binary built already; otherwise a dev build (the crate at
# opt-level 1: fast enough, and the bits do not depend on the profile).
bin=${SUBSET_VALIDATION_BIN:-}
if [ -z "$bin" ]; then
    cargo build --quiet --example subset_validation
    bin=${CARGO_TARGET_DIR:-target}/debug/examples/subset_validation
fi
mkdir -p "$dir"

runs() {
    "$bin" exact 150 > "$dir/exact.csv.tmp" && mv "$dir/exact.csv.tmp" "$dir/exact.csv"
    {
        "$bin" design A 30
        "$bin" design B 30 | tail -n +2
    } > "$dir/designs.csv.tmp" && mv "$dir/designs.csv.tmp" "$dir/designs.csv"
}

report() {
    "$bin" report "$dir" > results/subset_validation.md.tmp
    mv results/subset_validation.md.tmp results/subset_validation.md
}

case "${1:-}" in
    --mc)
        n=${2:-1000000}
        {
            echo "design,realizations,passed,not_ok,seed"
            "$bin" mc A "$n" 67
            "$bin" mc B "$n" 68
        } > "$dir/mc.csv.tmp" && mv "$dir/mc.csv.tmp" "$dir/mc.csv"
        runs
        report
        ;;
    --report)
        report
        ;;
    --check)
        "$bin" report "$dir" | diff -u results/subset_validation.md - \
            || { echo "results/subset_validation.md does not regenerate from $dir" >&2; exit 1; }
        tmp=$(mktemp)
        trap 'rm -f "$tmp"' EXIT
        "$bin" exact 3 1e-3 > "$tmp"
        { head -1 "$dir/exact.csv"; grep -E '^1e-3,[012],' "$dir/exact.csv"; } | diff -u - "$tmp" \
            || { echo "the exact slice of $dir/exact.csv is not reproduced" >&2; exit 1; }
        "$bin" design A 1 > "$tmp"
        { head -1 "$dir/designs.csv"; grep -E '^A,0,' "$dir/designs.csv"; } | diff -u - "$tmp" \
            || { echo "design A's run 0 in $dir/designs.csv is not reproduced" >&2; exit 1; }
        echo "subset validation: the report and the slices reproduce"
        ;;
    "")
        runs
        report
        ;;
    *)
        echo "usage: scripts/subset_validation.sh [--mc [N] | --report | --check]" >&2
        exit 2
        ;;
esac
