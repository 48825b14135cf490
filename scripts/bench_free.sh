#!/usr/bin/env bash
# Issue 69, item 4: free decay end to end, this tool against another commit's, in one script run.
#
#   scripts/bench_free.sh BASE [ROUNDS]         (ROUNDS default 3)
#   BASE_BIN=/path/to/impactsweep NEW_BIN=/path/to/impactsweep scripts/bench_free.sh BASE
#
# The tool at BASE (built here in a temporary worktree unless BASE_BIN names its binary) and
# this one (NEW_BIN, or built here) run the same studies, alternating
# (base, new, base, new, ...) so that a change of load falls on both, each `impactsweep run
# --threads 1` timed by its CPU time (user + sys; the machine is shared):
#   1. clean: the Table I system over e in [0.6, 0.95], N runs (default 200,000; one case each),
#      as `scripts/bench_e2e.sh` 1.;
#   2. noisy: N/10 points x 11 cases (the ideal and ten noise seeds of the paper's noise, 5e-10
#      m^2 s at 1 ms), as `scripts/bench_e2e.sh` 2.; per noisy run = (CPU - the points' clean
#      share, from 1. of the same tool and round) / the noisy runs;
#   3. the bundled free-decay studies as they are: `configs/overnight.toml` (44,541 points x 28
#      cases: the ideal, 24 perturbed, 27 with noise), `configs/design-space.toml` (3,146 x 9)
#      and `configs/paper.toml` (51 x 12; small enough that process start counts); their run
#      counts are read from `impactsweep plan`;
#   4. the extremes (e near 0 and 1, tiny and large m and d, and the slowest of
#      examples/time_extremes, C = 50 times critical damping) as studies of 5,000 to 200,000
#      design points each (times NX_SCALE; a sweep over a sliver of the key, so that every run
#      is its own), noise-free and with the paper's noise on one case of two.
# Prints each figure's median over the rounds, the ratio new / base, and whether the two tools
# wrote the same part files byte for byte (every study, last round; a part holds the study text
# and the tool's version, which both tools share here). Writes results/bench_free.md
# (or OUT) and prints it.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
base="${1:?usage: scripts/bench_free.sh BASE [ROUNDS]}"
rounds="${2:-3}"
out="${OUT:-results/bench_free.md}"
N=${N:-200000}
target="${CARGO_TARGET_DIR:-$ROOT/target}"
work=$(mktemp -d)
cleanup() {
  git worktree remove --force "$work/base" > /dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
NX_SCALE=${NX_SCALE:-1}
if [ -z "${NEW_BIN:-}" ]; then
  cargo build --release --quiet --bin impactsweep
  NEW_BIN="$target/release/impactsweep"
fi
if [ -z "${BASE_BIN:-}" ]; then
  git worktree add --quiet --detach "$work/base" "$base"
  (cd "$work/base" && CARGO_TARGET_DIR="$work/base-target" cargo build --release --quiet \
    --bin impactsweep)
  BASE_BIN="$work/base-target/release/impactsweep"
fi

study() { # NAME RUNS [noisy]
  {
    echo "[study]"
    echo "name = \"$1\""
    echo "seed = 1"
    echo 'outputs = ["xmax", "di"]'
    echo "[sweep]"
    echo "e = { start = 0.6, stop = 0.95, num = $2 }"
    if [ "${3:-}" = noisy ]; then
      echo "[noise]"
      echo "power = 5e-10"
      echo "sample_time = 1e-3"
      echo "[perturb]"
      echo "noise_seeds = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]"
    fi
  } > "$work/$1.toml"
}
study clean "$N"
study noisy "$((N / 10))" noisy
: > "$work/bundled.txt"
for s in overnight design-space paper; do
  cp "configs/$s.toml" "$work/$s.toml"
  echo "$s $("$NEW_BIN" plan "$work/$s.toml" | awk '/^total runs:/ { print $3 }')" >> "$work/bundled.txt"
done
studies="clean noisy overnight design-space paper"

extreme() { # NAME SYSTEM-LINE KEY START STOP RUNS (RUNS x SCALE design points)
  local num
  num=$(python3 -c "print(max(1, round($6 * $NX_SCALE)))")
  for noisy in "" "-noisy"; do
    {
      echo "[study]"
      echo "name = \"x-$1$noisy\""
      echo "seed = 1"
      echo 'outputs = ["xmax", "di"]'
      [ -n "$2" ] && printf '[system]\n%s\n' "$2"
      printf '[sweep]\n%s = { start = %s, stop = %s, num = %s }\n' "$3" "$4" "$5" "$num"
      if [ -n "$noisy" ]; then
        printf '[noise]\npower = 5e-10\nsample_time = 1e-3\n[perturb]\nnoise_seeds = [1]\n'
      fi
    } > "$work/x-$1$noisy.toml"
    echo "x-$1$noisy $num" >> "$work/xruns.txt"
    studies="$studies x-$1$noisy"
  done
}
: > "$work/xruns.txt"
extreme e0 "" e 0.0 1e-9 100000
extreme e1 "" e 0.999999 1.0 100000
extreme m-tiny "e = 0.9" m 1e-10 1.1e-10 100000
extreme m-large "e = 0.9" m 10.0 10.001 100000
extreme d-tiny "e = 0.9" d 1e-9 1.1e-9 5000
extreme d-large "e = 0.9" d 1e3 1.001e3 200000
extreme c-heavy "e = 0.9" C 632.0 633.0 5000

up0=$(uptime | sed 's/.*load average: //')
: > "$work/times.txt"
for i in $(seq "$rounds"); do
  for tool in base new; do
    bin=$BASE_BIN
    [ "$tool" = new ] && bin=$NEW_BIN
    for s in $studies; do
      rm -rf "$work/out-$tool"
      /usr/bin/time -f "%e %U %S" -o "$work/time.txt" "$bin" run "$work/$s.toml" \
        --out "$work/out-$tool" --threads 1 --quiet
      echo "$i $tool $s $(cat "$work/time.txt")" >> "$work/times.txt"
      [ "$i" = "$rounds" ] && mv "$work/out-$tool/$s" "$work/keep-$tool-$s"
    done
  done
done
up1=$(uptime | sed 's/.*load average: //')
: > "$work/same.txt"
for s in $studies; do
  same=yes
  for f in "$work/keep-base-$s"/points/*.parquet; do
    cmp -s "$f" "$work/keep-new-$s/points/$(basename "$f")" || same=no
  done
  echo "$s $same" >> "$work/same.txt"
done

python3 - "$work" "$N" "$rounds" "$base" "$up0" "$up1" > "$out" <<'PYEOF'
import statistics, subprocess, sys
work, n, rounds, base, up0, up1 = sys.argv[1:]
n, rounds = int(n), int(rounds)
xruns = {l.split()[0]: int(l.split()[1]) for l in open(f"{work}/xruns.txt")}
runs = {"clean": n, "noisy": n // 10 * 11}
runs.update({l.split()[0]: int(l.split()[1]) for l in open(f"{work}/bundled.txt")})
cpu = {}  # (tool, study) -> [cpu s per round]
for line in open(f"{work}/times.txt"):
    i, tool, s, wall, u, sy = line.split()
    cpu.setdefault((tool, s), []).append(float(u) + float(sy))
med = lambda v: statistics.median(v)
commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
model = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
same = dict(l.split() for l in open(f"{work}/same.txt"))
print("## Free decay end to end, base against new (issue 69)\n")
print(f"`scripts/bench_free.sh {base} {rounds}` at `{commit}` on {model}, "
      f"{subprocess.run(['nproc'], capture_output=True, text=True).stdout.strip()} cores; "
      f"load average before / after: {up0} / {up1}. `impactsweep run --threads 1`, CPU time (user + sys), "
      f"median of {rounds} interleaved rounds.\n")
print("| study | runs | base µs per run | new µs per run | new / base | same part files |")
print("|---|---|---|---|---|---|")
per = {}
for s in ["clean", "noisy", "overnight", "design-space", "paper"]:
    b = [c * 1e6 / runs[s] for c in cpu[("base", s)]]
    w = [c * 1e6 / runs[s] for c in cpu[("new", s)]]
    per[s] = (med(b), med(w))
    # A study under the timer's 10-ms tick (paper.toml on a quick machine) reads 0 s: no ratio.
    ratio = f"{med(w) / med(b):.3f}" if med(b) > 0 else "n/a"
    print(f"| {s} | {runs[s]:,} | {med(b):.2f} | {med(w):.2f} | {ratio} | {same[s]} |")
# Per noisy run: the noisy study less its points' clean share, round by round.
np = n // 10
def noisy_per_run(tool):
    v = []
    for c_noisy, c_clean in zip(cpu[(tool, "noisy")], cpu[(tool, "clean")]):
        clean_us = c_clean * 1e6 / n
        v.append((c_noisy * 1e6 - np * clean_us) / (np * 10))
    return med(v)
nb, nw = noisy_per_run("base"), noisy_per_run("new")
print(f"| per noisy run (noisy study less its clean runs) | {np * 10:,} | {nb:.2f} | {nw:.2f} | {nw / nb:.3f} | |")
print(f"\nNoisy / clean run: base {nb / per['clean'][0]:.2f}, new {nw / per['clean'][1]:.2f}.\n")
xs = sorted({s for (_, s) in cpu if s.startswith("x-")}, key=lambda s: (s.replace("-noisy", ""), s))
if xs:
    print("Extremes (the noisy study: the ideal case and one noisy case a design point), µs of CPU per run "
          "of the whole command:\n")
    print("| extreme | runs | base µs per run | new µs per run | new / base | same part files |")
    print("|---|---|---|---|---|---|")
    for s in xs:
        r = xruns[s] * (2 if s.endswith("-noisy") else 1)
        b = med([c * 1e6 / r for c in cpu[("base", s)]])
        w = med([c * 1e6 / r for c in cpu[("new", s)]])
        ratio = f"{w / b:.3f}" if b > 0 and w > 0 else "n/a"
        print(f"| {s[2:]} | {r:,} | {b:.2f} | {w:.2f} | {ratio} | {same[s]} |")
PYEOF
cat "$out"
