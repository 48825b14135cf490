#!/usr/bin/env bash
# The cost of capacities by incremental dynamic analysis (issue 67, "Speed"): the seismic
# showcase's 16 designs x 1,000 realizations with no stripes, so that every motion is run at
# its own scale and then searched for its capacity (configs/seismic.toml without its `im`
# axis). Prints the wall time of `run` and of `reduce`, the runs the capacity searches took,
# and the machine's load. A release build.
#
#   scripts/bench_ida.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
BIN=$PWD/target/release/impactsweep
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
sed -e 's/^name = "seismic"/name = "ida"/' -e '/^im = /d' -e '/^design_intensity/d' \
    configs/seismic.toml > "$WORK/ida.toml"
echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
start=$(date +%s.%N)
"$BIN" run "$WORK/ida.toml" --out "$WORK" --quiet
mid=$(date +%s.%N)
"$BIN" reduce "$WORK/ida" > /dev/null
end=$(date +%s.%N)
runs=$(awk -F, 'NR > 1 { s += $NF } END { print s }' "$WORK/ida/capacities.csv")
motions=$(($(wc -l < "$WORK/ida/capacities.csv") - 1))
awk -v s="$start" -v m="$mid" -v e="$end" -v n="$motions" -v r="$runs" 'BEGIN {
    printf "run %.1f s, reduce %.1f s; %d motions, %d runs in their capacity searches (%.2f a motion)\n",
        m - s, e - m, n, r, r / n }'
