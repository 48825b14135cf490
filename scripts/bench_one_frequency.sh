#!/usr/bin/env bash
# Issue 69, item 3: one-frequency studies of chaotic points (Table I's M and K, C = 0.1 N s/m,
# F0 = 0.1 N, 16 starts, the default design life of 1,000 h) at study seeds 1 to N, each `run`
# then `reduce`, one line per study: name, seed, run's wall and user seconds, reduce's wall and
# user seconds.
#
#   scripts/bench_one_frequency.sh BIN N NAME:m:d:r:e ...
#   e.g. scripts/bench_one_frequency.sh target/release/impactsweep 20 S4:0.02:0.01:0.9:0.9
set -euo pipefail
BIN=$1; N=$2; shift 2
w=$(mktemp -d)
trap 'rm -rf "$w"' EXIT
for spec in "$@"; do
  IFS=: read -r name m d r e <<< "$spec"
  for seed in $(seq 1 $N); do
    cat > $w/s.toml <<TOML
[study]
name = "one"
seed = $seed
[system]
M = 0.1
K = 400.0
C = 0.1
e = $e
m = $m
d = $d
x0 = 0.0
v0 = 0.0
y0 = 0.0
w0 = 0.0
[scene]
kind = "harmonic"
F0 = 0.1
r = $r
starts = 16
TOML
    rm -rf $w/o
    /usr/bin/time -f "%e %U" -o $w/t1 $BIN run $w/s.toml --out $w/o --quiet
    /usr/bin/time -f "%e %U" -o $w/t2 $BIN reduce $w/o/one > /dev/null
    echo "$name $seed $(cat $w/t1) $(cat $w/t2)"
  done
done
