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
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
TASKS="${1:-2}"
work=$(mktemp -d)
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
/usr/bin/time -f "%e %M" -o "$work/run.time" "$BIN" run "$work/space.toml" --out "$work/one" \
  >/dev/null 2>"$work/run.err" || { cat "$work/run.err" >&2; exit 1; }
/usr/bin/time -f "%e %M" -o "$work/reduce.time" "$BIN" reduce "$work/one/forced-space" \
  >/dev/null 2>"$work/reduce.err" || { cat "$work/reduce.err" >&2; exit 1; }
eval "$(scripts/slurm-local.sh start "$work/cluster" | grep '^SLURM_CONF=')"
export SLURM_CONF
t0=$(date +%s.%N)
"$BIN" slurm "$work/space.toml" --tasks "$TASKS" --cpus-per-task 1 --out "$work/slurm" \
  > "$work/submit.out"
# Every job of this private cluster done (4 h at most).
for _ in $(seq 1 14400); do
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
for f in "$work/one/forced-space"/*.csv; do
  b=$(basename "$f")
  if cmp -s "$f" "$run_dir/$b"; then same=$((same + 1)); else differ+=("$b"); fi
done
read -r run_s run_kb < "$work/run.time"
read -r red_s red_kb < "$work/reduce.time"
out=results/bench_forced_slurm.md
{
  echo "\`scripts/bench_forced_slurm.sh $TASKS\` on $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores, commit \`$(git rev-parse --short HEAD)\`, release build, one run of each."
  echo "\`uptime\` at start: \`$up0\`; at end: \`$up1\`."
  echo
  echo "The study: 1,000 designs (m x d x e at 10 values each) x 41 frequencies, one case, 8 census starts (41,000 runs)."
  echo
  echo "| path | wall (s) | peak memory (MiB) |"
  echo "|---|---|---|"
  echo "| one machine: \`run\` | $run_s | $((run_kb / 1024)) |"
  echo "| one machine: \`reduce\` | $red_s | $((red_kb / 1024)) |"
  echo "| one machine: end to end | $(awk -v a="$run_s" -v b="$red_s" 'BEGIN{printf "%.1f", a+b}') | |"
  echo "| \`impactsweep slurm --tasks $TASKS --cpus-per-task 1\` on the local single-node cluster, submission to empty queue | $slurm_wall | |"
  echo
  echo "- \`reduce\` against \`run\`: $(awk -v a="$run_s" -v b="$red_s" 'BEGIN{printf "%.3f", b/a}')."
  echo "- Reduced CSV tables the same bytes on both paths: $same of $((same + ${#differ[@]}))${differ:+ (differ: ${differ[*]})}."
} > "$out"
cat "$out"
