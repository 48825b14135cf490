#!/usr/bin/env bash
# Chunk bookkeeping benchmark (issue 9, item 3): the same 100,000 design points (e x m, one
# noise-free case, xmax and DI) run in 10, 40, 1,000, 10,000 and 100,000 chunks. For each: the
# wall time of `run` (2 threads), the time per chunk, the bookkeeping per chunk beyond the
# 10-chunk run, then `status` (verifies every part: one read and one xxh3 each) and a `run
# --resume` that finds everything done (verifies every part too). Then the checksum's own speed
# (`cargo bench --bench checksum`). Writes results/bench_chunks.md (and prints it).
#
# Usage: [BEFORE_MAX=N] scripts/bench_chunks.sh [BEFORE_BIN]
#   BEFORE_BIN: an impactsweep built before the journal (it rewrote manifest.json after every
#   chunk, e.g. `git archive <commit> | tar -x` and `cargo build --release`), timed up to
#   BEFORE_MAX chunks (default 1000; 10,000 takes it a minute and a half) for the "before" column.
# The work directory is $BENCH_DIR, else a temp directory under target/ (the disk the project
# is on; /tmp may be memory). The 100,000-chunk dataset takes about 1.1 GB while it exists.
set -euo pipefail
cd "$(dirname "$0")/.."
before=${1:-}
before_max=${BEFORE_MAX:-1000}
cargo build --release --quiet
bin=$PWD/target/release/impactsweep
mkdir -p target
work=$(mktemp -d "${BENCH_DIR:-$PWD/target}/bench_chunks.XXXXXX")
trap 'rm -rf "$work"' EXIT
points=100000

cat > "$work/chunks.toml" <<EOF
# Benchmark: 1000 x 100 = 100,000 design points, one noise-free case, two peaks per run.
[study]
name = "chunks"
seed = 1
outputs = ["xmax", "di"]

[sweep]
e = { start = 0.45, stop = 0.95, num = 1000 }
m = { start = 0.01, stop = 0.03, num = 100 }
EOF

# secs CMD...: wall seconds of a command (its output discarded).
secs() {
  local t0 t1
  t0=$(date +%s.%N)
  "$@" >/dev/null 2>&1
  t1=$(date +%s.%N)
  echo "$t1 - $t0" | bc -l
}
f() { printf "%.${2:-2}f" "$1"; }

load0=$(cut -d' ' -f1-3 /proc/loadavg)
up0=$(uptime)
rows=""
w10=""
for n in 10 40 1000 10000 100000; do
  cp=$((points / n))
  rm -rf "$work/out"
  wall=$(secs "$bin" run "$work/chunks.toml" --out "$work/out" --quiet --threads 2 --chunk-points "$cp")
  bytes=$(du -sb "$work/out/chunks/points" | cut -f1)
  st=$(secs "$bin" status "$work/out/chunks")
  res=$(secs "$bin" run "$work/chunks.toml" --out "$work/out" --quiet --threads 2 --resume)
  rm -rf "$work/out"
  [ -z "$w10" ] && w10=$wall
  per=$(echo "1000 * $wall / $n" | bc -l)
  if [ "$n" -gt 10 ]; then
    over=$(f "$(echo "1000 * ($wall - $w10) / ($n - 10)" | bc -l)" 3)
  else
    over="-"
  fi
  old="-"
  if [ -n "$before" ] && [ "$n" -le "$before_max" ]; then
    old=$(f "$(secs "$before" run "$work/chunks.toml" --out "$work/old" --quiet --threads 2 --chunk-points "$cp")")
    rm -rf "$work/old"
  fi
  rows+="| $n | $cp | $(f "$wall") | $(f "$per" 3) | $over | $(f "$(echo "$bytes / 1000000" | bc -l)" 1) | $(f "$st") | $(f "$res") | $old |"$'\n'
  echo "$n chunks: run $(f "$wall") s, status $(f "$st") s, resume $(f "$res") s" >&2
done
load1=$(cut -d' ' -f1-3 /proc/loadavg)
up1=$(uptime)

# The checksum's own speed (criterion, 8 MiB buffer).
sums=$(cargo bench --quiet --bench checksum -- --noplot 2>/dev/null | grep -E "^checksum|thrpt" || true)

model=$(lscpu | awk -F': +' '/Model name/ {print $2; exit}')
mkdir -p results
cat > results/bench_chunks.md <<EOF
## Chunk bookkeeping (issue 9)

\`scripts/bench_chunks.sh\` on $model, $(nproc) cores, $(free -g | awk '/Mem:/ {print $2}') GB RAM, $(df -T "$work" | awk 'NR==2 {print $2}') ($(date -u +%Y-%m-%d), \`$(git rev-parse --short HEAD)\`).
Release build; the same $points design points (one noise-free case each) in every row, \`run --quiet
--threads 2 --chunk-points P\`, one run each; wall time includes start-up, every part file, the
journal lines, the syncs (about one a second) and the final fold into \`manifest.json\`.
Load before: \`$up0\`; after: \`$up1\` (the machine is shared: other builders' load inflates
every figure).

| chunks | points per chunk | run wall (s) | per chunk (ms) | bookkeeping per extra chunk (ms) | dataset (MB) | \`status\` (s) | \`run --resume\`, all done (s) | before: run wall (s) |
|---|---|---|---|---|---|---|---|---|
$rows
- *bookkeeping per extra chunk*: (wall - wall of the 10-chunk run) / (chunks - 10): what one more
  chunk costs (a part file of its own, about 10.6 kB of footer, a journal line).
- *before*: \`$(basename "${before:-none}")\`, the engine that rewrote \`manifest.json\` after every
  chunk (timed up to $before_max chunks; issue 9 measured 74 s for 10,000 chunks and more than
  8 minutes for 100,000, with 20,000 points).
- \`status\` and \`run --resume\` read and hash every part (xxh3-64).

Checksum speed (\`cargo bench --bench checksum\`, 8 MiB in memory, one core):

\`\`\`text
$sums
\`\`\`
EOF
cat results/bench_chunks.md
