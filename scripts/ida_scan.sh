#!/usr/bin/env bash
# How far above the first passage the capacity search lands, and whether the first passage
# itself is a converged quantity (examples/ida_scan.rs): the seismic showcase's scene
# (configs/seismic.toml) at its 0.2-g design stripe, one design (m kg, d m) per argument pair.
# 1. R realizations a design, each motion run again on a 0.5 % grid of scales from half its
#    capacity up to it.
# 2. RR realizations a design (default 300), each motion run at every point of a grid of 5,600
#    steps (0.025 %) from a quarter of its capacity up to it, and its first passage read on the
#    nested grids of steps 2, 0.5, 0.12 and 0.025 %.
# Writes results/ida_scan.md (or OUT) and prints it; without designs, the five of that file: no
# damper, and four dampers across the showcase's grid. A measurement, never a test.
#
#   scripts/ida_scan.sh [R [M D [M D ...]]]      (R default 300; about 15 minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
R=${1:-300}
RR=${RR:-300}
[ $# -gt 0 ] && shift
[ $# -gt 0 ] || set -- 0.0 0.01 0.2 0.005 0.1 0.01 0.05 0.02 0.2 0.04
out=${OUT:-results/ida_scan.md}
cargo build --quiet --example ida_scan
bin=target/debug/examples/ida_scan
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
designs=()
while [ $# -ge 2 ]; do
    designs+=("$1 $2")
    for n in "$R" "$RR"; do
        sed -e "s/^realizations = .*/realizations = $n/" -e "s/^m = .*/m = [$1]/" -e "s/^d = .*/d = [$2]/" \
            -e 's/^im = .*/im = [0.2]/' configs/seismic.toml > "$WORK/design_$1_$2_$n.toml"
    done
    shift 2
done
# Each design's two measurements, as many at once as there are cores.
for md in "${designs[@]}"; do
    set -- $md
    echo "$bin $WORK/design_$1_$2_$R.toml $R > $WORK/scan_$1_$2"
    echo "IDA_LEVELS=80,20,5,1 $bin $WORK/design_$1_$2_$RR.toml $RR 5600 0.25 > $WORK/levels_$1_$2"
done | xargs -P "$(nproc)" -I{} sh -c '{}'
{
    echo "# Capacities against the first passage"
    echo
    echo "\`scripts/ida_scan.sh $R\` (\`examples/ida_scan.rs\`): \`configs/seismic.toml\`'s scene at its"
    echo "0.2-g design stripe, $R realizations a design. Each motion's capacity as the sweep stores"
    echo "it, then the motion run again at 141 scales on a geometric grid from half that capacity up"
    echo "to it (a 0.50 % step), and \`capacity / smallest scale that passes\` (1 where none below"
    echo "passes). A monotone response gives 1 to the grid's step; above it, the search reported a"
    echo "later crossing than the first. Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)."
    echo
    echo "| design | motions | search runs | median | 90 % | 99 % | max | over 1.01 | over 1.05 | over 1.1 | geometric mean |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|"
    for md in "${designs[@]}"; do
        set -- $md
        echo "| m = $1 kg, d = $2 m | $(cat "$WORK/scan_$1_$2") |"
    done
    echo
    echo "## The first passage against the grid's step"
    echo
    echo "$RR realizations a design (\`IDA_LEVELS=80,20,5,1\`). Each motion run at every point of a"
    echo "geometric grid of 5,600 steps (0.025 %) from a quarter of its capacity up to it, and its"
    echo "first passage read on the nested grids that keep every 80th, 20th, 5th and every point"
    echo "(steps 2, 0.5, 0.12 and 0.025 %; the capacity, the grid's top, is on all of them):"
    echo "\`first passage / capacity\` (1 where none passes), the median number of passing windows"
    echo "(runs of passing points) a motion's grid shows, and the share of motions whose first passage"
    echo "lies more than 1 % below the next coarser grid's."
    echo
    echo "| design | step | motions | first / capacity, geometric mean | median | 5 % | least | passing windows, median | moved > 1 % |"
    echo "|---|---|---|---|---|---|---|---|---|"
    for md in "${designs[@]}"; do
        set -- $md
        while IFS= read -r row; do
            echo "| m = $1 kg, d = $2 m | $row |"
        done < "$WORK/levels_$1_$2"
    done
} > "$WORK/out.md"
mv "$WORK/out.md" "$out"
cat "$out"
