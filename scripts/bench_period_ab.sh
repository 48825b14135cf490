#!/usr/bin/env bash
# Two builds of the simulator side by side on the same fixed workload (`examples/period_cost.rs`:
# issue 43's eight chaotic points, N periods each located in full and N with the floor, one
# thread), measured two ways:
#
# 1. Instructions executed (valgrind's cachegrind, `--cache-sim=no`), the whole workload and the
#    functions that execute the most. A count, not a time: the same binary gives the same count
#    on any load, so a change of a few per cent shows. It weighs a square root or a division
#    like an addition, so it is a guide, not a verdict: at stop 56 the x86-64-v3 build executed
#    12.6 % fewer instructions and ran the showcase no faster on an Intel Xeon (at stop 110,
#    0.94 of the time on an AMD EPYC; BENCHMARKS.md). Time a change that counts fewer on the
#    showcase end to end (scripts/bench_ab.sh) before keeping it. Valgrind 3.19 stops on an AVX
#    instruction of the harmonic scene in an x86-64-v3 build (the project's default on x86-64):
#    count builds made with `RUSTFLAGS=`.
# 2. Wall time, both builds at the same time, each pinned to its own core, swapping cores every
#    round, so a change of the machine's speed falls on both alike. On the 2-core KVM machine of
#    BENCHMARKS.md one build run alone drifts by +-15 % from run to run; two builds' ratio in a
#    shared round still moves by about +-10 %, so take the median of several rounds.
#
# Prints both, and whether every point's maxima agree bit for bit (a change that must keep every
# bit shows that it did).
#
#   scripts/bench_period_ab.sh A_BIN B_BIN [ROUNDS] [N]     (ROUNDS default 4, N default 20000)
#
# `A_ARGS` and `B_ARGS` (environment) are passed after N to each side: one binary then runs both
# of the harmonic scene's event finders (issue 69), e.g.
# `A_ARGS=safe_steps B_ARGS=bracketed scripts/bench_period_ab.sh BIN BIN`.
#
# A_BIN and B_BIN are `period_cost` binaries, e.g. target/release/examples/period_cost of two
# worktrees (`cargo build --release --example period_cost` in each). The instruction counts run
# N / 4 periods under valgrind (about 30 s per build at N = 20000); without valgrind they are
# left out (`apt-get install valgrind`).
set -euo pipefail
a=${1:?usage: scripts/bench_period_ab.sh A_BIN B_BIN [ROUNDS] [N]}
b=${2:?usage: scripts/bench_period_ab.sh A_BIN B_BIN [ROUNDS] [N]}
rounds=${3:-4}
n=${4:-20000}
[ "$(nproc)" -ge 2 ] || { echo "needs two cores" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
strip() { sed -n 's/^\([A-Z0-9]* floor [0-9.]*\): [0-9.]* us\/period, \(.*\), [0-9.]* steps\/period$/\1 \2/p' "$1"; }
echo "A: $a"
echo "B: $b"
echo
if command -v valgrind > /dev/null; then
  ni=$((n / 4))
  echo "## Instructions ($ni periods per point and floor, cachegrind)"
  echo
  for x in a b; do
    bin=$a
    [ "$x" = b ] && bin=$b
    valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file="$work/cg.$x" \
      "$bin" "$ni" $([ "$x" = a ] && echo "${A_ARGS:-}" || echo "${B_ARGS:-}") > "$work/ir.$x" 2> "$work/vg.$x"
  done
  ir() { sed -n 's/.*I *refs: *\([0-9,]*\).*/\1/p' "$work/vg.$1" | tr -d ,; }
  ia=$(ir a)
  ib=$(ir b)
  echo "| build | instructions | B / A |"
  echo "|---|---|---|"
  echo "| A | $ia | |"
  echo "| B | $ib | $(awk "BEGIN { printf \"%.3f\", $ib / $ia }") |"
  for x in a b; do
    echo
    echo "The functions of $(tr a-z A-Z <<< "$x") that execute the most:"
    echo
    cg_annotate "$work/cg.$x" 2> /dev/null | sed -n '/file:function/,/^$/p' | sed -n '3,12p' \
      | sed -e 's/^ */    /' -e 's#/[^ ]*/src/#src/#' | cut -c1-150
  done
  echo
fi
echo "## Wall time ($n periods per point and floor, both builds at once, pinned)"
echo
echo "uptime: $(uptime)"
echo
echo "| round | cores (A, B) | A (us/period) | B (us/period) | B / A |"
echo "|---|---|---|---|---|"
per() { sed -n 's/^all: \([0-9.]*\) us\/period$/\1/p' "$1"; }
for i in $(seq "$rounds"); do
  if [ $((i % 2)) = 1 ]; then ca=0; cb=1; else ca=1; cb=0; fi
  # shellcheck disable=SC2086
  taskset -c "$ca" "$a" "$n" ${A_ARGS:-} > "$work/a$i" 2> /dev/null &
  # shellcheck disable=SC2086
  taskset -c "$cb" "$b" "$n" ${B_ARGS:-} > "$work/b$i" 2> /dev/null
  wait
  ta=$(per "$work/a$i")
  tb=$(per "$work/b$i")
  awk -v i="$i" -v c="$ca, $cb" -v ta="$ta" -v tb="$tb" \
    'BEGIN { printf "| %d | %s | %s | %s | %.3f |\n", i, c, ta, tb, tb / ta }'
  awk -v ta="$ta" -v tb="$tb" 'BEGIN { print tb / ta }' >> "$work/ratios"
done
echo
echo "Median B / A over $rounds rounds: $(sort -g "$work/ratios" \
  | awk '{ r[NR] = $1 } END { printf "%.3f", (NR % 2) ? r[(NR + 1) / 2] : 0.5 * (r[NR / 2] + r[NR / 2 + 1]) }')."
echo "uptime: $(uptime)"
echo
if diff -q <(strip "$work/a1") <(strip "$work/b1") > /dev/null; then
  echo "Every point's maxima: the same bits."
else
  echo "The maxima differ (a change of bits):"
  diff <(strip "$work/a1") <(strip "$work/b1") | sed 's/^/    /' || true
fi
