#!/usr/bin/env bash
# How far below the capacities the search reports the same motions already pass the limit
# (examples/ida_scan.rs): the seismic showcase's scene (configs/seismic.toml) at its 0.2-g design
# stripe, one design (m kg, d m) per argument pair, R realizations each (default 300), each
# motion rescanned on a 0.5 % grid from half its capacity up to it. One line per design.
#
#   scripts/ida_scan.sh [R] M D [M D ...]      e.g. scripts/ida_scan.sh 300 0.1 0.01 0.2 0.005
set -euo pipefail
cd "$(dirname "$0")/.."
R=${1:?usage: scripts/ida_scan.sh R M D [M D ...]}
shift
cargo build --quiet --example ida_scan
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
while [ $# -ge 2 ]; do
    sed -e "s/^realizations = .*/realizations = $R/" -e "s/^m = .*/m = [$1]/" -e "s/^d = .*/d = [$2]/" \
        -e 's/^im = .*/im = [0.2]/' configs/seismic.toml > "$WORK/design.toml"
    echo "m = $1 kg, d = $2 m: $(target/debug/examples/ida_scan "$WORK/design.toml" "$R")"
    shift 2
done
