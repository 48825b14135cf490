#!/usr/bin/env bash
# Sweep benchmark (issue 3, item 7): a 10^6-run noise-free two-peak sweep (e x m x d, 100 values
# each, one case per point) with 2 threads and with 1 thread, then a noisy variant, on this
# machine. Measures wall time, runs/s, peak RSS (/usr/bin/time -v, else /proc), the efficiency
# of 2 threads against 1, and the cost of noise per noisy run. Writes results/bench_sweep.md
# (and prints it).
#
# Usage: scripts/bench_sweep.sh [N_PER_AXIS]     (default 100: 100^3 = 10^6 runs)
# Targets: <= 20 s wall for 10^6 runs on 2 cores, <= 256 MB peak RSS, >= 90 % 2-thread efficiency.
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-100}
cargo build --release --quiet
bin=$PWD/target/release/impactsweep
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cat > "$work/bench.toml" <<EOF
# Benchmark: noise-free, two peaks per run (xmax and DI), $n^3 runs.
[study]
name = "bench"
seed = 1
outputs = ["xmax", "di"]

[sweep]
e = { start = 0.45, stop = 0.95, num = $n }
m = { start = 0.01, stop = 0.03, num = $n }
d = { start = 0.005, stop = 0.015, num = $n }
EOF

# Noisy variant: e x m = 100 x 100 points, the ideal case plus 9 noisy cases = 10^5 runs, of
# which 9 in 10 draw noise (configs/paper.toml's noise: 5e-10 m^2 s at 1 ms).
cat > "$work/noisy.toml" <<EOF
[study]
name = "noisy"
seed = 1
outputs = ["xmax", "di"]

[sweep]
e = { start = 0.45, stop = 0.95, num = $n }
m = { start = 0.01, stop = 0.03, num = $n }

[noise]
power = 5e-10
sample_time = 1e-3

[perturb]
noise_seeds = [1, 2, 3, 4, 5, 6, 7, 8, 9]
EOF

# Same grid and case count without noise, to isolate the cost of noise.
cat > "$work/clean10.toml" <<EOF
[study]
name = "clean10"
seed = 1
outputs = ["xmax", "di"]

[sweep]
e = { start = 0.45, stop = 0.95, num = $n }
m = { start = 0.01, stop = 0.03, num = $n }
d = { start = 0.00991, stop = 0.01, num = 10 }
EOF

have_time=0
if /usr/bin/time -v true >/dev/null 2>&1; then have_time=1; fi

# best NAME STUDY THREADS: the faster of two runs (the machine is shared; the minimum is the
# least disturbed measurement) -> WALL RSS CPU RUNS DISK
best() {
  run "$@"
  local w=$WALL r=$RSS c=$CPU
  run "$@"
  if [ "$(echo "$w < $WALL" | bc -l)" = 1 ]; then WALL=$w; RSS=$r; CPU=$c; fi
}

# run NAME STUDY THREADS -> sets WALL (s) RSS (kB) CPU (user + sys s) RUNS DISK
run() {
  local name=$1 study=$2 threads=$3
  rm -rf "$work/out"
  local t0 t1
  t0=$(date +%s.%N)
  if [ $have_time = 1 ]; then
    /usr/bin/time -v -o "$work/time.txt" "$bin" run "$study" --out "$work/out" --threads "$threads" --quiet
    RSS=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$work/time.txt")
    CPU=$(awk -F': ' '/User time/ {u=$2} /System time/ {s=$2} END {print u + s}' "$work/time.txt")
  else
    "$bin" run "$study" --out "$work/out" --threads "$threads" --quiet &
    local pid=$! peak=0 r
    while kill -0 $pid 2>/dev/null; do
      r=$(awk '/VmHWM/ {print $2}' /proc/$pid/status 2>/dev/null || echo 0)
      [ -n "$r" ] && [ "$r" -gt "$peak" ] && peak=$r
      sleep 0.05
    done
    wait $pid
    RSS=$peak
    CPU=0
  fi
  t1=$(date +%s.%N)
  WALL=$(echo "$t1 - $t0" | bc -l)
  RUNS=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['runs_done'])" "$work/out/$name/manifest.json")
  DISK=$(du -sk "$work/out/$name/points" | cut -f1)
}

load0=$(cut -d' ' -f1-3 /proc/loadavg)
autogroup=$(cat /proc/self/autogroup 2>/dev/null || echo "n/a")
best bench "$work/bench.toml" 2
w2=$WALL; rss2=$RSS; cpu2=$CPU; runs=$RUNS; disk=$DISK
best bench "$work/bench.toml" 1
w1=$WALL; rss1=$RSS; cpu1=$CPU
best noisy "$work/noisy.toml" 2
wn=$WALL; rssn=$RSS; cpun=$CPU; runs_n=$RUNS
best clean10 "$work/clean10.toml" 2
wc=$WALL; cpuc=$CPU; runs_c=$RUNS
load1=$(cut -d' ' -f1-3 /proc/loadavg)

model=$(lscpu | awk -F': +' '/Model name/ {print $2; exit}')
cores=$(nproc)
mem=$(free -g | awk '/Mem:/ {print $2}')
f() { printf "%.${2:-2}f" "$1"; }
rate2=$(echo "$runs / $w2" | bc -l)
rate1=$(echo "$runs / $w1" | bc -l)
eff=$(echo "100 * $w1 / (2 * $w2)" | bc -l)
# CPU time per run (user + sys), which other load on the machine disturbs less than wall time.
us_clean=$(echo "1000000 * $cpuc / $runs_c" | bc -l)
us_noisy=$(echo "1000000 * $cpun / $runs_n" | bc -l)
# 9 of 10 runs of the noisy study draw noise.
us_noise=$(echo "($us_noisy - $us_clean) * 10 / 9" | bc -l)

mkdir -p results
cat > results/bench_sweep.md <<EOF
## Sweep

\`scripts/bench_sweep.sh\` on $model, $cores cores, $mem GB RAM ($(date -u +%Y-%m-%d), \`$(git rev-parse --short HEAD)\`).
Release build; \`impactsweep run --quiet\`, best of two runs each; wall time includes start-up,
the Parquet writes (each part synced before its rename) and the manifest updates. Load average
before/after: $load0 / $load1; scheduler group: $autogroup. (Linux shares the CPU between
sessions (autogroups), so on a shared machine run the benchmark in its own session with a raised
group priority: \`sudo setsid sh -c 'echo -15 > /proc/self/autogroup && scripts/bench_sweep.sh'\`.)

| sweep | runs | threads | wall (s) | runs/s | CPU (s) | peak RSS (MB) |
|---|---|---|---|---|---|---|
| e × m × d, noise-free, 2 peaks | $runs | 2 | $(f "$w2") | $(f "$rate2" 0) | $(f "$cpu2" 1) | $(f "$(echo "$rss2/1024" | bc -l)" 0) |
| same | $runs | 1 | $(f "$w1") | $(f "$rate1" 0) | $(f "$cpu1" 1) | $(f "$(echo "$rss1/1024" | bc -l)" 0) |
| e × m × 10 cases, 9 noisy | $runs_n | 2 | $(f "$wn") | $(f "$(echo "$runs_n / $wn" | bc -l)" 0) | $(f "$cpun" 1) | $(f "$(echo "$rssn/1024" | bc -l)" 0) |
| e × m × 10 clearances, noise-free | $runs_c | 2 | $(f "$wc") | $(f "$(echo "$runs_c / $wc" | bc -l)" 0) | $(f "$cpuc" 1) | |

- Two-thread efficiency: $(f "$eff" 1) % (\`T1 / (2 T2)\`).
- CPU time per run: $(f "$us_clean") µs noise-free, $(f "$us_noisy") µs in the noisy study; the
  noise costs about $(f "$us_noise") µs per noisy run (one Gaussian per 1 ms sample inside the
  positive half-cycles).
- Dataset size: $(f "$(echo "$disk/1024" | bc -l)" 1) MB of Parquet for $runs runs
  ($(f "$(echo "$disk * 1024 / $runs" | bc -l)" 1) bytes per run).
- Targets: ≤ 20 s wall for 10^6 runs on 2 cores, ≤ 256 MB peak RSS, ≥ 90 % efficiency.
EOF
cat results/bench_sweep.md
