#!/usr/bin/env bash
# Issue 11's whole-command figures, in one script run on this machine:
#   1. noise-free µs per run of the whole `impactsweep run` command, one thread, default chunking:
#      the Table I system over e in [0.6, 0.95] (one case per point), best of three by CPU time;
#   2. µs per noisy run: the same sweep with the paper's noise (5e-10 m^2 s at 1 ms) and ten noise
#      seeds (11 cases per point, 10 noisy), less the noise-free share measured in 1.;
#   3. the SciPy peer (scripts/peer_scipy.py, DOP853 at rtol 1e-10 with wall events and a restart
#      at each impact) on the same system for e = 0.60, 0.61, ..., 0.95, and its ratio to 1.;
#   4. two-thread efficiency T1 / (2 T2) of a 10^6-run noise-free sweep (wall time);
#   5. the extremes table (examples/time_extremes, CPU time per run): the slowest one;
#   6. where a whole `run` spends its time at 10^3, 10^5 and 10^7 runs (default threads):
#      process start (the wall time of `impactsweep --version` against the command's), and
#      `perf` CPU samples by function: planning (study parsing, grids, plan), simulation,
#      Parquet encoding, the manifest, the system (kernel, allocator, memcpy) and the rest.
# Writes results/bench_e2e.md and prints it. N=... overrides the runs of 1. (default 200000),
# SIZES=... the sizes of 6. (default "1000 100000 10000000").
#
# The machine may be shared: the load average is printed before and after, CPU time (user +
# sys) is the headline for 1. and 2., and 4. (wall time) is only meaningful on an idle machine or
# in a session of raised priority: setsid sh -c 'echo -15 > /proc/self/autogroup && scripts/bench_e2e.sh'.
# Instruction counts, which load does not disturb, are in BENCHMARKS.md ("Profile").
set -euo pipefail
cd "$(dirname "$0")/.."
PY="${IMPACTSWEEP_PYTHON:-$PWD/.venv/bin/python}"
[ -x "$PY" ] || { scripts/setup-python.sh; PY="$PWD/.venv/bin/python"; }
N=${N:-200000}
cargo build --release --quiet --bin impactsweep --example time_extremes
bin=$PWD/target/release/impactsweep
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=results/bench_e2e.md
load0=$(uptime | sed 's/.*load average: //')
autogroup=$(cat /proc/self/autogroup 2>/dev/null || echo "n/a")
model=$(lscpu | awk -F': +' '/Model name/ {print $2; exit}')

study() { # NAME RUNS [noisy]
  local name=$1 n=$2
  {
    echo "[study]"
    echo "name = \"$name\""
    echo "seed = 1"
    echo 'outputs = ["xmax", "di"]'
    echo "[sweep]"
    echo "e = { start = 0.6, stop = 0.95, num = $n }"
    if [ "${3:-}" = noisy ]; then
      echo "[noise]"
      echo "power = 5e-10"
      echo "sample_time = 1e-3"
      echo "[perturb]"
      echo "noise_seeds = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]"
    fi
  } > "$work/$name.toml"
}

# run_once STUDY THREADS -> WALL CPU (s)
run_once() {
  rm -rf "$work/out"
  /usr/bin/time -f "%e %U %S" -o "$work/time.txt" "$bin" run "$work/$1.toml" --out "$work/out" \
    --threads "$2" --quiet
  read -r WALL u s < "$work/time.txt"
  CPU=$(echo "$u + $s" | bc -l)
  rm -rf "$work/out"
}

# best STUDY THREADS REPS -> WALL CPU of the least disturbed run (least CPU), and BEST_WALL
best() {
  local bw=1000000000 bc=1000000000 bcw=0 i
  for i in $(seq "$3"); do
    run_once "$1" "$2"
    if [ "$(echo "$CPU < $bc" | bc -l)" = 1 ]; then bc=$CPU; bcw=$WALL; fi
    if [ "$(echo "$WALL < $bw" | bc -l)" = 1 ]; then bw=$WALL; fi
  done
  CPU=$bc; WALL=$bcw; BEST_WALL=$bw
}

# 1. noise-free, one thread.
study clean "$N"
best clean 1 3
us_clean=$(echo "1000000 * $CPU / $N" | bc -l)
us_clean_wall=$(echo "1000000 * $BEST_WALL / $N" | bc -l)

# 2. noisy: N/10 points x 11 cases, 10 of them noisy.
np=$((N / 10))
study noisy "$np" noisy
best noisy 1 3
runs_noisy=$((np * 11))
us_noisy_study=$(echo "1000000 * $CPU / $runs_noisy" | bc -l)
us_noisy=$(echo "(1000000 * $CPU - $np * $us_clean) / ($np * 10)" | bc -l)

# 3. the SciPy peer on the same system, e = 0.60 ... 0.95.
es=()
for i in $(seq 0 35); do es+=(--e "$(printf '0.%02d' $((60 + i)))"); done
"$PY" scripts/peer_scipy.py --method DOP853 --reps 3 --json "${es[@]}" > "$work/peer.json"

# 4. two-thread efficiency, 10^6 runs.
study big "${N_BIG:-1000000}"
best big 1 2
t1=$BEST_WALL; cpu1=$CPU
best big 2 2
t2=$BEST_WALL; cpu2=$CPU
eff=$(echo "$t1 / (2 * $t2)" | bc -l)

# 5. extremes.
target/release/examples/time_extremes > "$work/extremes.json"

# 6. shares at 10^3 (x 100 processes), 10^5 and 10^7 runs.
for i in $(seq 20); do
  t0=$(date +%s%N); "$bin" --version > /dev/null; t1ns=$(date +%s%N)
  echo $(( (t1ns - t0) / 1000 ))
done | sort -n | head -n 1 > "$work/start.txt"
start_us=$(cat "$work/start.txt")
have_perf=0
if command -v perf > /dev/null && perf record -e cpu-clock -o "$work/probe.data" true > /dev/null 2>&1; then
  have_perf=1
fi
: > "$work/shares.txt"
for n in ${SIZES:-1000 100000 10000000}; do
  study "s$n" "$n"
  reps=1; freq=500
  [ "$n" = 1000 ] && { reps=100; freq=4000; }
  [ "$n" = 100000 ] && freq=4000
  cat > "$work/loop.sh" <<EOF
for i in \$(seq $reps); do "$bin" run "$work/s$n.toml" --out "$work/o\$i" --quiet; done
EOF
  # Wall time without perf (its own start-up would count), then the samples with it.
  t0=$(date +%s%N)
  sh "$work/loop.sh"
  t1ns=$(date +%s%N)
  echo "$n $reps $(( (t1ns - t0) / 1000 ))" >> "$work/shares.txt"
  rm -rf "$work"/o*
  if [ $have_perf = 1 ]; then
    perf record -q -e cpu-clock -F $freq -o "$work/perf.data" sh "$work/loop.sh" > /dev/null 2>&1
    perf report -i "$work/perf.data" --no-children --sort dso,sym --stdio 2> /dev/null \
      | grep -E '^ +[0-9]' > "$work/perf$n.txt" || true
    rm -rf "$work"/o*
  else
    : > "$work/perf$n.txt"
  fi
done
load1=$(uptime | sed 's/.*load average: //')

"$PY" - "$work" "$us_clean" "$us_clean_wall" "$us_noisy" "$us_noisy_study" "$t1" "$t2" "$eff" \
  "$cpu1" "$cpu2" "$start_us" "$have_perf" "$N" "$load0" "$load1" "$model" "$autogroup" > "$out" <<'PYEOF'
import json, re, subprocess, sys
(work, us_clean, us_clean_wall, us_noisy, us_noisy_study, t1, t2, eff, cpu1, cpu2, start_us,
 have_perf, n, load0, load1, model, autogroup) = sys.argv[1:]
us_clean, us_clean_wall, us_noisy, us_noisy_study = map(float, (us_clean, us_clean_wall, us_noisy, us_noisy_study))
t1, t2, eff, cpu1, cpu2, start_us = map(float, (t1, t2, eff, cpu1, cpu2, start_us))
peer = json.load(open(f"{work}/peer.json"))["methods"][0]
done = [r for r in peer["runs"] if r["outcome"] != "chatter"]
peer_us = peer["time_per_run_s"] * 1e6
peer_cpu_us = peer["cpu_per_run_s"] * 1e6
ratio, ratio_cpu = peer_us / us_clean_wall, peer_cpu_us / us_clean
ext = json.load(open(f"{work}/extremes.json"))["rows"]
timed = [r for r in ext if "seconds_per_run" in r]
slow = max(timed, key=lambda r: r["seconds_per_run"])
commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()

def classify(dso, sym):
    if "impactsweep::sim::" in sym or dso.startswith("libm") or "simulate_chunk" in sym \
            or "run_row" in sym or "Plan::run" in sym or "noise" in sym:
        return "simulation"
    if re.search(r"parquet::|arrow|snap::|impactsweep::store|thrift|ahash|encode", sym):
        return "Parquet encoding"
    if re.search(r"serde_json|manifest|Manifest|fnv|checksum", sym):
        return "manifest"
    if re.search(r"impactsweep::study|impactsweep::plan|round_sig15|toml|flt2dec|dec2flt|model::System", sym):
        return "planning"
    if dso.startswith("[kernel") or dso.startswith("libc") or dso.startswith("ld-"):
        return "system (kernel, allocator, memcpy)"
    return "other"

classes = ["planning", "simulation", "Parquet encoding", "manifest", "system (kernel, allocator, memcpy)", "other"]
rows = []
for line in open(f"{work}/shares.txt"):
    size, reps, wall_us = line.split()
    size, reps, wall_us = int(size), int(reps), float(wall_us)
    per_cmd_us = wall_us / reps
    share = {c: 0.0 for c in classes}
    for l in open(f"{work}/perf{size}.txt"):
        m = re.match(r"\s*([\d.]+)%\s+(\S+)\s+\[.\]\s+(.*)", l)
        if m:
            share[classify(m.group(2), m.group(3))] += float(m.group(1))
    rows.append((size, per_cmd_us, per_cmd_us / size, 100 * start_us / per_cmd_us, share))

def mark(ok):
    return "met" if ok else "**not met**"

print("## Whole command (issue 11)\n")
print(f"`scripts/bench_e2e.sh` on {model}, {subprocess.run(['nproc'], capture_output=True, text=True).stdout.strip()} cores, commit `{commit}`.")
print(f"Load average before / after: {load0} / {load1}; scheduler group {autogroup} (the machine is shared: CPU")
print("time is the headline; on a shared machine run it as `setsid sh -c 'echo -15 > /proc/self/autogroup &&")
print("scripts/bench_e2e.sh'` so that the wall times, the two-thread efficiency above all, mean something).\n")
print("| what | measured | target |")
print("|---|---|---|")
print(f"| noise-free run, whole `run` command, one thread (Table I, e in [0.6, 0.95], {int(n):,} runs) | {us_clean:.2f} µs CPU ({us_clean_wall:.2f} µs wall) | ≤ 4 µs (at least ≤ 5.5): {mark(us_clean <= 4.0)} |")
print(f"| noisy run (paper's noise, 1 ms samples), same command | {us_noisy:.2f} µs CPU ({us_noisy_study:.2f} µs per run of the 11-case study) | |")
print(f"| noisy / noise-free | {us_noisy / us_clean:.2f} | ≤ 1.5, aim 1.2: {mark(us_noisy / us_clean <= 1.5)} |")
print(f"| SciPy DOP853 (rtol 1e-10, events, restart per impact) per run / ours | {ratio:.0f}x wall ({peer_us / 1e3:.2f} ms), {ratio_cpu:.0f}x CPU | ≥ 1000x, aim 1500x: {mark(ratio >= 1000)} |")
print(f"| two-thread efficiency T1 / (2 T2), 10^6 runs | {eff:.3f} (T1 {t1:.2f} s, T2 {t2:.2f} s wall; CPU {cpu1:.2f} / {cpu2:.2f} s) | ≥ 0.9: {mark(eff >= 0.9)} |")
print(f"| slowest extreme, per run | {slow['seconds_per_run'] * 1e6:.0f} µs CPU ({slow['name']}{', noisy' if slow['noisy'] else ''}: {slow['outcome']}, {slow['steps']} steps) | ≤ 1 ms: {mark(slow['seconds_per_run'] <= 1e-3)} |")
print()
print(f"The peer finished {len(done)} of {len(peer['runs'])} runs (the others are chatter it cannot get past; they are left out of its time).\n")
print("Where a whole `run` (default threads and chunking, noise-free) spends its time: process start is the wall time of")
print(f"`impactsweep --version` ({start_us:.0f} µs) against the command's; the rest are shares of the `perf` CPU samples by function" + ("" if have_perf == "1" else " (perf is not available here: not measured)") + ".\n")
print("| runs | wall per command | µs per run (wall) | process start | " + " | ".join(classes) + " |")
print("|---|---|---|---|" + "---|" * len(classes))
for size, per_cmd, per_run, start, share in rows:
    print(f"| {size:,} | {per_cmd / 1e6:.3f} s | {per_run:.2f} | {start:.1f} % | " + " | ".join(f"{share[c]:.1f} %" for c in classes) + " |")
print()
print("Extremes (examples/time_extremes, CPU time per run, default solver and request):\n")
print("| extreme | noise | outcome | impacts | steps | µs per run |")
print("|---|---|---|---|---|---|")
for r in ext:
    if "refused" in r:
        if not r["noisy"]:
            print(f"| {r['name']} | | refused: {r['refused']} | | | |")
        continue
    print(f"| {r['name']} | {'yes' if r['noisy'] else ''} | {r['outcome']} | {r['impacts']} | {r['steps']} | {r['seconds_per_run'] * 1e6:.2f} |")
PYEOF
cat "$out"
