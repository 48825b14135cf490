#!/usr/bin/env bash
# Issue 23, item 6: the forced design space of scripts/bench_forced_scale.sh (1,000 designs: m x d
# x e at 10 values each, 41 frequencies, one case, 8 census starts) on one machine, then through
# `impactsweep slurm` on the real single-node cluster of scripts/slurm-local.sh (the sweep's
# array, the analysis array, the dependent reduce), in one script run. Wall times (GNU time for
# the single machine; from submission until the cluster's queue is empty for Slurm), peak
# memory, and whether the reduced tables (every CSV the reduce writes) are the same bytes.
# Writes results/bench_forced_slurm.md and prints it.
#
#   scripts/bench_forced_slurm.sh [TASKS]      (array tasks, default 2: one per core here)
#   ONE_MACHINE=0 scripts/bench_forced_slurm.sh   (the Slurm path only)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
TASKS="${1:-2}"
work=$(mktemp -d)
# The cluster's munge user must reach the state directory under it.
chmod 755 "$work"
cleanup() {
  scripts/slurm-local.sh stop "$work/cluster" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
cargo build --release --quiet
BIN="$ROOT/target/release/impactsweep"
# The study, as bench_forced_scale.sh writes it (one copy of its text).
sed -n '/^cat > "\$work\/space.toml" <<.TOML./,/^TOML$/p' scripts/bench_forced_scale.sh \
  | sed '1d;$d' > "$work/space.toml"
grep -q 'name = "forced-space"' "$work/space.toml"
up0=$(uptime)
# ONE_MACHINE=0 skips the single machine's run and reduce (and the comparison of the tables).
if [ "${ONE_MACHINE:-1}" != 0 ]; then
  /usr/bin/time -f "%e %M" -o "$work/run.time" "$BIN" run "$work/space.toml" --out "$work/one" \
    >/dev/null 2>"$work/run.err" || { cat "$work/run.err" >&2; exit 1; }
  /usr/bin/time -f "%e %M" -o "$work/reduce.time" "$BIN" reduce "$work/one/forced-space" \
    >/dev/null 2>"$work/reduce.err" || { cat "$work/reduce.err" >&2; exit 1; }
fi
scripts/slurm-local.sh start "$work/cluster" > "$work/cluster.out"
SLURM_CONF=$(sed -n 's/^SLURM_CONF=//p' "$work/cluster.out")
[ -n "$SLURM_CONF" ] || { echo "the local cluster did not start" >&2; exit 1; }
export SLURM_CONF
t0=$(date +%s.%N)
"$BIN" slurm "$work/space.toml" --tasks "$TASKS" --cpus-per-task 1 --out "$work/slurm" \
  > "$work/submit.out"
# Every job of this private cluster done (4 h at most); when each phase's jobs (the sweep's
# array, the analysis array, the reduce) left the queue.
name=impactsweep-forced-space
phase_end() { # PHASE: seconds since submission when no job of PHASE is queued any more
  [ -f "$work/end-$1" ] && return
  if ! squeue -h -o '%j' 2>/dev/null | grep -qx "$2"; then
    awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}' > "$work/end-$1"
  fi
}
for _ in $(seq 1 14400); do
  phase_end sweep "$name"
  phase_end analysis "$name-analysis"
  phase_end reduce "$name-reduce"
  [ -z "$(squeue -h 2>/dev/null)" ] && break
  sleep 1
done
t1=$(date +%s.%N)
[ -z "$(squeue -h)" ] || { echo "jobs still queued after 4 h" >&2; exit 1; }
up1=$(uptime)
slurm_wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.1f", b-a}')
run_dir="$work/slurm/forced-space"
[ -f "$run_dir/report.md" ] || { echo "the reduce job wrote no report:" >&2; cat "$run_dir"/slurm/logs/* >&2; exit 1; }
same=0
differ=()
if [ "${ONE_MACHINE:-1}" != 0 ]; then
  for f in "$work/one/forced-space"/*.csv; do
    b=$(basename "$f")
    if cmp -s "$f" "$run_dir/$b"; then same=$((same + 1)); else differ+=("$b"); fi
  done
  read -r run_s run_kb < "$work/run.time"
  read -r red_s red_kb < "$work/reduce.time"
fi
sweep_end=$(cat "$work/end-sweep")
analysis_end=$(cat "$work/end-analysis")
reduce_end=$(cat "$work/end-reduce")
out=results/bench_forced_slurm.md
{
  echo "\`scripts/bench_forced_slurm.sh $TASKS\` on $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores, commit \`$(git rev-parse --short HEAD)\`, release build, one run of each."
  echo "\`uptime\` at start: \`$up0\`; at end: \`$up1\`."
  echo
  echo "The study: 1,000 designs (m x d x e at 10 values each) x 41 frequencies, one case, 8 census starts (41,000 runs)."
  echo
  echo "| path | wall (s) | peak memory (MiB) |"
  echo "|---|---|---|"
  if [ "${ONE_MACHINE:-1}" != 0 ]; then
    echo "| one machine: \`run\` | $run_s | $((run_kb / 1024)) |"
    echo "| one machine: \`reduce\` | $red_s | $((red_kb / 1024)) |"
    echo "| one machine: end to end | $(awk -v a="$run_s" -v b="$red_s" 'BEGIN{printf "%.1f", a+b}') | |"
  fi
  echo "| \`impactsweep slurm --tasks $TASKS --cpus-per-task 1\` on the local single-node cluster, submission to empty queue | $slurm_wall | |"
  echo "| of which: the sweep's array done | $sweep_end | |"
  echo "| the analysis array done | $analysis_end | |"
  echo "| the final reduce done | $reduce_end | |"
  echo
  echo "- On the cluster, the analysis array and the final \`reduce\` against the sweep's array: $(awk -v a="$sweep_end" -v b="$analysis_end" -v c="$reduce_end" 'BEGIN{printf "%.3f (analysis array %.1f s, reduce %.1f s, sweep %.1f s)", (c-a)/a, b-a, c-b, a}')."
  if [ "${ONE_MACHINE:-1}" != 0 ]; then
    echo "- One machine, \`reduce\` against \`run\`: $(awk -v a="$run_s" -v b="$red_s" 'BEGIN{printf "%.3f", b/a}')."
    echo "- Reduced CSV tables the same bytes on both paths: $same of $((same + ${#differ[@]}))${differ:+ (differ: ${differ[*]})}."
  fi
} > "$out"
cat "$out"
