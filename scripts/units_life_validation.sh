#!/usr/bin/env bash
# The design life of several units against brute force (issue 68):
# results/units_life_validation.md and its data (examples/units_life_validation.rs).
#
#   scripts/units_life_validation.sh           brute force (100 blocks of 10^6 periods per point),
#                                              the estimates (2 points, 20 study seeds, 2 horizons)
#                                              and the report: about 25 minutes on 2 cores
#   scripts/units_life_validation.sh --report  the report alone, from the committed files
#   scripts/units_life_validation.sh --check   what CI runs: the report regenerates byte for byte
#                                              from the committed files, and a slice of the
#                                              estimates (U2, seed 1) is reproduced bit for bit
set -euo pipefail
cd "$(dirname "$0")/.."
dir=results/units_life_validation
# UNITS_LIFE_VALIDATION_BIN: an example binary built already (scripts/test.sh builds it in the
# test profile for --check: the bits do not depend on the profile); otherwise a release build.
bin=${UNITS_LIFE_VALIDATION_BIN:-}
if [ -z "$bin" ]; then
  cargo build --release --quiet --example units_life_validation
  bin=target/release/examples/units_life_validation
fi

report() {
  "$bin" report > results/units_life_validation.md.tmp
  mv results/units_life_validation.md.tmp results/units_life_validation.md
}

case "${1:-}" in
  --report) report ;;
  --check)
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    "$bin" report > "$tmp/report.md"
    cmp "$tmp/report.md" results/units_life_validation.md
    "$bin" estimate 1..1 U2 > "$tmp/slice.csv"
    head -n 1 "$dir/estimates.csv" > "$tmp/want.csv"
    grep -E '^U2,1,' "$dir/estimates.csv" >> "$tmp/want.csv"
    cmp "$tmp/slice.csv" "$tmp/want.csv"
    echo "units_life_validation: the report and the slice (U2, seed 1) reproduce"
    ;;
  "")
    mkdir -p "$dir/brute"
    for name in U1 U2; do
      "$bin" brute "$name" 100 > "$dir/brute/$name.csv.tmp"
      mv "$dir/brute/$name.csv.tmp" "$dir/brute/$name.csv"
    done
    "$bin" estimate > "$dir/estimates.csv.tmp"
    mv "$dir/estimates.csv.tmp" "$dir/estimates.csv"
    report
    ;;
  *) echo "usage: $0 [--report | --check]" >&2; exit 2 ;;
esac
