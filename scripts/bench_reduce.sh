#!/usr/bin/env bash
# Times `impactsweep reduce` on a 10^6-run dataset and prints the table of BENCHMARKS.md's Reduce section.
#
#   scripts/bench_reduce.sh [WORK_DIR]     (default: a temporary directory, removed afterwards)
#
# The dataset: configs/paper.toml with e on 83,334 values (x 12 cases = 1,000,008 runs, the
# paper's noise and perturbations). It is swept once, then reduced twice (best of two) with
# the study's 2000 bootstrap resamples, and once with 1 resample to show what the bootstrap
# costs. Wall time, CPU time and peak RSS from /usr/bin/time.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ge 1 ]; then WORK=$1; mkdir -p "$WORK"; else WORK=$(mktemp -d); trap 'rm -rf "$WORK"' EXIT; fi
cargo build --release --quiet
BIN=$(pwd)/target/release/impactsweep
sed 's/^name = "paper".*/name = "million"/; s/^e = {.*/e = { start = 0.45, stop = 0.95, num = 83334 }/' \
    configs/paper.toml > "$WORK/million.toml"
[ -d "$WORK/million/points" ] || "$BIN" run "$WORK/million.toml" --out "$WORK" --quiet
mkdir -p "$WORK/b1"
ln -sfn "$WORK/million/points" "$WORK/b1/points"
sed 's/^bootstrap = .*/bootstrap = 1/' "$WORK/million/study.toml" > "$WORK/b1/study.toml"

measure() { # dir -> "wall cpu rss_mb"
    /usr/bin/time -f "%e %U %S %M" "$BIN" reduce "$1" > /dev/null 2> "$WORK/time.txt"
    tail -n 1 "$WORK/time.txt" | awk '{printf "%.2f %.2f %.0f\n", $1, $2 + $3, $4 / 1024}'
}
best() { # dir -> best of two by wall time
    a=$(measure "$1"); b=$(measure "$1")
    if awk -v a="${a%% *}" -v b="${b%% *}" 'BEGIN{exit !(a <= b)}'; then echo "$a"; else echo "$b"; fi
}
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
full=$(best "$WORK/million")
boot1=$(best "$WORK/b1")
load_after=$(cut -d' ' -f1-3 /proc/loadavg)
size=$(du -sm "$WORK/million/points" | cut -f1)
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')
echo "## Reduce"
echo
echo "\`scripts/bench_reduce.sh\` on $cpu, $(nproc) cores ($(date -u +%F), \`$(git rev-parse --short HEAD)\`)."
echo "Release build; \`impactsweep reduce\` of 1,000,008 runs (83,334 design points x 12 cases, ${size} MB"
echo "of Parquet), best of two; wall time includes reading every part file, the outputs and the"
echo "charts. Load average before/after: $load_before / $load_after (the machine is shared)."
echo
echo "| bootstrap resamples | wall (s) | CPU (s) | peak RSS (MB) |"
echo "|---|---|---|---|"
read -r w c m <<< "$full"; echo "| 2000 (the study's) | $w | $c | $m |"
read -r w c m <<< "$boot1"; echo "| 1 | $w | $c | $m |"
