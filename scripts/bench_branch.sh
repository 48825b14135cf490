#!/usr/bin/env bash
# Issue 16's speed figure: a point on a continued periodic branch against the transient run at
# the same frequency (examples/time_branch.rs, same release build), with the machine and load.
# Writes results/bench_branch.md and prints it.
set -euo pipefail
cd "$(dirname "$0")/.."
out=results/bench_branch.md
up0=$(uptime)
json=$(cargo run --release --quiet --example time_branch -- "${1:-5}")
up1=$(uptime)
{
  echo "# A point on a continued branch against a transient run (issue 16)"
  echo
  echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $(uname -sr)."
  echo "Load before: ${up0##*load average: }; after: ${up1##*load average: }."
  echo
  echo "Design: M = 0.1 kg, K = 400 N/m, C = 0.1 N s/m, m = 5 g, d = 5 mm, e = 0.9, F0 = 0.1 N;"
  echo "the stable two-impact branch from r = 0.80 to 0.86. Medians over repetitions, one run."
  echo
  echo '```json'
  echo "$json"
  echo '```'
} > "$out"
cat "$out"
