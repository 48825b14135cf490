#!/usr/bin/env bash
# How far above the first passage the capacity search lands (examples/ida_scan.rs): the seismic
# showcase's scene (configs/seismic.toml) at its 0.2-g design stripe, one design (m kg, d m) per
# argument pair, R realizations each, each motion run again on a 0.5 % grid of scales from half
# its capacity up to it. Writes results/ida_scan.md (or OUT) and prints it; without designs,
# the five of that file: no damper, and four dampers across the showcase's grid.
#
#   scripts/ida_scan.sh [R [M D [M D ...]]]      (R default 300; about a minute on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
R=${1:-300}
[ $# -gt 0 ] && shift
[ $# -gt 0 ] || set -- 0.0 0.01 0.2 0.005 0.1 0.01 0.05 0.02 0.2 0.04
out=${OUT:-results/ida_scan.md}
cargo build --quiet --example ida_scan
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
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
    while [ $# -ge 2 ]; do
        sed -e "s/^realizations = .*/realizations = $R/" -e "s/^m = .*/m = [$1]/" -e "s/^d = .*/d = [$2]/" \
            -e 's/^im = .*/im = [0.2]/' configs/seismic.toml > "$WORK/design.toml"
        echo "| m = $1 kg, d = $2 m | $(target/debug/examples/ida_scan "$WORK/design.toml" "$R") |"
        shift 2
    done
} > "$WORK/out.md"
mv "$WORK/out.md" "$out"
cat "$out"
