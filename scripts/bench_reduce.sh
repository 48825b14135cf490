#!/usr/bin/env bash
# Times `impactsweep reduce` on 10^6 and 10^7 runs and prints the table of BENCHMARKS.md's
# Reduce section.
#
#   scripts/bench_reduce.sh [WORK_DIR]     (default: a temporary directory, removed afterwards)
#
# The datasets: configs/paper.toml with e on 83,334 and 833,334 values (x 12 cases =
# 1,000,008 and 10,000,008 runs, the paper's noise and perturbations; the second is over the
# size guard and runs with --allow-large). Each is swept once (kept in WORK_DIR for a re-run),
# then reduced twice (best of two) with the study's 2000 bootstrap resamples, and twice with
# `--bootstrap 1` to show what the bootstrap costs. Wall time, CPU time and peak RSS from
# /usr/bin/time; the load average before and after each measurement (the machine is shared:
# measure when it is quiet).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ge 1 ]; then WORK=$1; mkdir -p "$WORK"; else WORK=$(mktemp -d); trap 'rm -rf "$WORK"' EXIT; fi
cargo build --release --quiet
BIN=$(pwd)/target/release/impactsweep

dataset() { # name points
    sed "s/^name = \"paper\".*/name = \"$1\"/; s/^e = {.*/e = { start = 0.45, stop = 0.95, num = $2 }/" \
        configs/paper.toml > "$WORK/$1.toml"
    [ -f "$WORK/$1/manifest.json" ] && "$BIN" status "$WORK/$1" | grep -q '^complete' \
        || "$BIN" run "$WORK/$1.toml" --out "$WORK" --quiet --allow-large --resume
}

measure() { # dir bootstrap -> "wall cpu rss_mb"
    /usr/bin/time -f "%e %U %S %M" "$BIN" reduce "$1" --bootstrap "$2" > /dev/null 2> "$WORK/time.txt"
    tail -n 1 "$WORK/time.txt" | awk '{printf "%.2f %.2f %.0f\n", $1, $2 + $3, $4 / 1024}'
}
best() { # dir bootstrap -> best of two by wall time
    a=$(measure "$1" "$2"); b=$(measure "$1" "$2")
    if awk -v a="${a%% *}" -v b="${b%% *}" 'BEGIN{exit !(a <= b)}'; then echo "$a"; else echo "$b"; fi
}
load() { cut -d' ' -f1-3 /proc/loadavg; }
commas() { echo "$1" | sed ':a;s/\B[0-9]\{3\}\>/,&/;ta'; }

cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')
echo "## Reduce"
echo
echo "\`scripts/bench_reduce.sh\` on $cpu, $(nproc) cores ($(date -u +%F), \`$(git rev-parse --short HEAD)\`)."
echo "Release build; \`impactsweep reduce\` of the paper's study with e on 83,334 and 833,334 values"
echo "(12 cases), best of two; wall time includes reading every part file, the extra simulations"
echo "of the jumps, the outputs and the charts."
echo
echo "| runs | design points | Parquet (MB) | bootstrap | wall (s) | CPU (s) | peak RSS (MB) | load before / after |"
echo "|---|---|---|---|---|---|---|---|"
for spec in "million 83334 1,000,008" "tenmillion 833334 10,000,008"; do
    read -r name points runs <<< "$spec"
    dataset "$name" "$points"
    size=$(du -sm "$WORK/$name/points" | cut -f1)
    for boot in 2000 1; do
        before=$(load)
        read -r w c m <<< "$(best "$WORK/$name" "$boot")"
        after=$(load)
        echo "| $runs | $(commas "$points") | $size | $boot | $w | $c | $m | $before / $after |"
    done
done
