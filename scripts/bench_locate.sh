#!/usr/bin/env bash
# Issue 24's cost figures: a located bifurcation against an ordinary continuation point, and a
# point of a two-parameter bifurcation curve, on the issue's study (examples/locate_cost.rs,
# same release build), with the machine and load.
# Writes results/bench_locate.md and prints it.
set -euo pipefail
cd "$(dirname "$0")/.."
out=results/bench_locate.md
up0=$(uptime)
json=$(cargo run --release --quiet --example locate_cost -- "${1:-5}")
up1=$(uptime)
{
  echo "# Located bifurcations and two-parameter curves against continuation points (issue 24)"
  echo
  echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $(uname -sr)."
  echo "Load before: ${up0##*load average: }; after: ${up1##*load average: }."
  echo
  echo "Design: M = 0.1 kg, K = 400 N/m, C = 0.1 N s/m, m = 5 g, d = 5 mm, e = 0.9, F0 = 0.1 N;"
  echo "every branch through the periodic attractors of a 48-start census at r = 0.85 ... 1.15 by"
  echo "0.01, followed as reduce follows them (doubled branches included). Median wall time over"
  echo "repetitions, one run; the time is split between continuation steps and locating in"
  echo "proportion to the forcing periods each simulated. Locating periods include attempts that"
  echo "found no root (a sign change through a jump). Second line: every located fold, doubling"
  echo "and Neimark-Sacker point followed in (r, d) over d = 4.5 ... 5.5 mm (grid 4.5, 5, 5.5 mm);"
  echo "third line: every located grazing followed the same way."
  echo
  echo '```json'
  echo "$json"
  echo '```'
} > "$out"
cat "$out"
