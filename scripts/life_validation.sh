#!/usr/bin/env bash
# The design life against brute force (issue 43): results/life_validation.md and its data.
#
#   scripts/life_validation.sh           the estimates (every point, 20 study seeds, three
#                                        horizons: about an hour on 2 cores) and the report
#   scripts/life_validation.sh --brute   brute force first: 64 runs of 10^6 periods per point
#                                        (about 8 CPU-hours in all), then the above
#   scripts/life_validation.sh --report  the report alone, from the committed files
#   scripts/life_validation.sh --check   what CI runs: the report regenerates byte for byte from
#                                        the committed estimates and brute force, and a slice of
#                                        the estimates (point P2, seeds 1 and 2) is reproduced
#                                        bit for bit (every column but the wall time)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=results/life_validation
cargo build --release --quiet --example life_validation
bin=target/release/examples/life_validation

brute() {
    mkdir -p "$dir/brute"
    # name, seed (each point its own stream of starts)
    for p in P1:101 P2:102 S1:103 S2:104 S3:105 S4:106 S5:107 S6:108; do
        "$bin" brute "${p%%:*}" 64 "${p##*:}" > "$dir/brute/${p%%:*}.json.tmp"
        mv "$dir/brute/${p%%:*}.json.tmp" "$dir/brute/${p%%:*}.json"
    done
}

report() {
    "$bin" report "$dir" > results/life_validation.md.tmp
    mv results/life_validation.md.tmp results/life_validation.md
}

case "${1:-}" in
    --brute)
        brute
        "$bin" estimate 20 > "$dir/estimates.csv.tmp" && mv "$dir/estimates.csv.tmp" "$dir/estimates.csv"
        report
        ;;
    --report)
        report
        ;;
    --check)
        "$bin" report "$dir" | diff -u results/life_validation.md - \
            || { echo "results/life_validation.md does not regenerate from $dir" >&2; exit 1; }
        # Every column but the wall time (column 11).
        "$bin" estimate 2 P2 | cut -d, -f1-10,12 > /tmp/life_slice.$$.csv
        { head -1 "$dir/estimates.csv"; grep '^P2,[12],' "$dir/estimates.csv"; } | cut -d, -f1-10,12 \
            | diff -u - /tmp/life_slice.$$.csv \
            || { rm -f /tmp/life_slice.$$.csv; echo "the P2 slice of $dir/estimates.csv is not reproduced" >&2; exit 1; }
        rm -f /tmp/life_slice.$$.csv
        echo "life validation: the report and the P2 slice reproduce"
        ;;
    "")
        "$bin" estimate 20 > "$dir/estimates.csv.tmp" && mv "$dir/estimates.csv.tmp" "$dir/estimates.csv"
        report
        ;;
    *)
        echo "usage: scripts/life_validation.sh [--brute | --report | --check]" >&2
        exit 2
        ;;
esac
