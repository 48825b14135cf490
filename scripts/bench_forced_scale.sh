#!/usr/bin/env bash
# Issues 22 and 23's figures, in one script run on this machine (release builds, every core):
#   1. the showcase (configs/frequency-response.toml: 9 designs x 5 cases x 81 frequencies, 8
#      census starts) run and reduced by the tool before issue 23 (commit OLD, default e53b9e3,
#      built here in a temporary worktree unless OLD_BIN names its binary) and by this one;
#   2. the same study with one start (`starts = 1`, `design_peak = "from_rest"`) by this one:
#      the census's cost relative to one start, end to end; and with window peaks
#      (`nonperiodic_peak = "window"`): the work that existed before the design life, without it;
#   2b. the same study with a shorter cap on each life estimate (`life_max_periods` = 10,000
#      and 5,000 against the default 20,000): what the design life's cost buys, end to end and
#      in the ideal design peaks and ranks;
#   3. examples/race_cost: the periods the census simulates, the motions that are not periodic
#      and the periods their life amplitudes cost by the race against refining every one;
#   4. a forced design space of 1,000 designs (m x d x e at 10 values each, 41 frequencies,
#      one case, 8 starts): run and reduce, wall time and peak memory (GNU time's max RSS).
# Writes results/bench_forced_scale.md (figures, machine, load, commit) and prints it.
#
#   scripts/bench_forced_scale.sh [OLD]
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
old="${1:-e53b9e3}"
work=$(mktemp -d)
cleanup() {
  git worktree remove --force "$work/old" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
cargo build --release --quiet
cargo build --release --quiet --example race_cost
NEW="$ROOT/target/release/impactsweep"
if [ -z "${OLD_BIN:-}" ]; then
  git worktree add --quiet --detach "$work/old" "$old"
  (cd "$work/old" && CARGO_TARGET_DIR="$work/old-target" cargo build --release --quiet)
  OLD_BIN="$work/old-target/release/impactsweep"
fi
up0=$(uptime)
# time_cmd LABEL CMD...: appends "LABEL seconds max_rss_kB" to $work/times.
time_cmd() {
  local label=$1
  shift
  /usr/bin/time -f "$label %e %M" -a -o "$work/times" "$@" >/dev/null 2>"$work/$label.err" \
    || { cat "$work/$label.err" >&2; exit 1; }
}
sed -e 's/^starts = 8/starts = 1/' -e 's/^design_peak = "worst"/design_peak = "from_rest"/' \
  configs/frequency-response.toml > "$work/one-start.toml"
grep -q '^starts = 1' "$work/one-start.toml"
sed -e 's/^design_peak = "worst"/design_peak = "worst"\nnonperiodic_peak = "window"/' \
  configs/frequency-response.toml > "$work/window.toml"
grep -q '^nonperiodic_peak = "window"' "$work/window.toml"
for cap in 10000 5000; do
  sed -e "s/^design_peak = \"worst\"/design_peak = \"worst\"\nlife_max_periods = $cap/" \
    configs/frequency-response.toml > "$work/cap$cap.toml"
  grep -q "^life_max_periods = $cap" "$work/cap$cap.toml"
done
time_cmd old_run "$OLD_BIN" run configs/frequency-response.toml --out "$work/old"
time_cmd old_reduce "$OLD_BIN" reduce "$work/old/frequency-response"
time_cmd new_run "$NEW" run configs/frequency-response.toml --out "$work/new"
time_cmd new_reduce "$NEW" reduce "$work/new/frequency-response"
time_cmd one_run "$NEW" run "$work/one-start.toml" --out "$work/one"
time_cmd one_reduce "$NEW" reduce "$work/one/frequency-response"
time_cmd win_run "$NEW" run "$work/window.toml" --out "$work/win"
time_cmd win_reduce "$NEW" reduce "$work/win/frequency-response"
for cap in 10000 5000; do
  time_cmd "cap${cap}_run" "$NEW" run "$work/cap$cap.toml" --out "$work/cap$cap"
  time_cmd "cap${cap}_reduce" "$NEW" reduce "$work/cap$cap/frequency-response"
done
"$ROOT/target/release/examples/race_cost" > "$work/race.json"
cat > "$work/space.toml" <<'TOML'
[study]
name = "forced-space"
seed = 23
[system]
M = 0.1
K = 400.0
C = 0.1
x0 = 0.0
v0 = 0.0
y0 = 0.0
w0 = 0.0
[scene]
kind = "harmonic"
F0 = 0.1
starts = 8
[sweep]
m = { start = 0.002, stop = 0.02, step = 0.002 }
d = { start = 0.002, stop = 0.02, step = 0.002 }
e = { start = 0.5, stop = 0.95, step = 0.05 }
r = { start = 0.8, stop = 1.2, step = 0.01 }
[reliability]
strength_mean = 100e6
strength_sd = 8e6
TOML
time_cmd space_run "$NEW" run "$work/space.toml" --out "$work/space"
time_cmd space_reduce "$NEW" reduce "$work/space/forced-space"
up1=$(uptime)
PY="${IMPACTSWEEP_PYTHON:-$ROOT/.venv/bin/python}"
[ -x "$PY" ] || PY=python3
"$PY" - "$work" "$old" "$up0" "$up1" > results/bench_forced_scale.md <<'PYEOF'
import csv, json, subprocess, sys
work, old, up0, up1 = sys.argv[1:5]
t = {}
for line in open(f"{work}/times"):
    label, sec, rss = line.split()
    t[label] = (float(sec), int(rss) / 1024)
race = json.load(open(f"{work}/race.json"))
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
nproc = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
n_space = subprocess.run(["grep", "-c", "", f"{work}/space.toml"], capture_output=True, text=True).stdout.strip()
def e2e(k): return t[f"{k}_run"][0] + t[f"{k}_reduce"][0]
print("## The forced design space at scale and the design life (issues 22, 23)\n")
print(f"`scripts/bench_forced_scale.sh` on {cpu}, {nproc} cores, commit `{commit}` against `{old}`, release builds, one run of each.")
print(f"`uptime` at start: `{up0.strip()}`; at end: `{up1.strip()}`.\n")
print("| what | run (s) | reduce (s) | end to end (s) | peak memory (MiB) |\n|---|---|---|---|---|")
for k, name in [("old", f"showcase, before (`{old}`)"), ("new", "showcase, now"), ("one", "showcase, now, one start (`starts = 1`, `from_rest`)"), ("win", "showcase, now, window peaks (`nonperiodic_peak = \"window\"`: no design life)"), ("cap10000", "showcase, now, `life_max_periods = 10000`"), ("cap5000", "showcase, now, `life_max_periods = 5000`"), ("space", "1,000 designs x 41 frequencies, 1 case, 8 starts")]:
    r, d = t[f"{k}_run"], t[f"{k}_reduce"]
    print(f"| {name} | {r[0]:.1f} | {d[0]:.1f} | {r[0] + d[0]:.1f} | {max(r[1], d[1]):.0f} |")
print()
print(f"- Showcase end to end: {e2e('old'):.1f} s before, {e2e('new'):.1f} s now ({e2e('old') / e2e('new'):.2f}x faster), design-life estimates included.")
print(f"- The census against one start, end to end: {e2e('new') / e2e('one'):.2f}x.")
def rows(k):
    with open(f"{work}/{k}/frequency-response/summary.csv", newline="") as fh:
        return {r["point"]: r for r in csv.DictReader(fh)}
def peaks(k):
    return {p: float(r["peak_amplitude_ideal"]) for p, r in rows(k).items()}
base = rows("new")
life, win = peaks("new"), peaks("win")
ratios = [win[p] / life[p] for p in life]
print(f"- Without the design life (window peaks), the work that existed before it (census, the sweeps up and down, continuation, jumps): {e2e('win'):.1f} s end to end, {e2e('old') / e2e('win'):.2f}x faster than before; the design life is {1 - e2e('win') / e2e('new'):.0%} of the showcase now. The ideal window peaks are {min(ratios):.3f} to {max(ratios):.3f} times the life peaks.")
caps = {c: rows(f"cap{c}") for c in (10000, 5000)}
for c, rs in caps.items():
    rat = [float(rs[p]["peak_amplitude_ideal"]) / life[p] for p in life]
    moved = sum(rs[p]["rank"] != base[p]["rank"] for p in life)
    print(f"- A shorter cap on each life estimate, `life_max_periods = {c}` (default 20,000): {e2e(f'cap{c}'):.1f} s end to end; the ideal design peaks are {min(rat):.3f} to {max(rat):.3f} times the default's, and {moved} of {len(life)} designs change rank.")
print()
print("| m (kg) | d (m) | peak, default (cm) | its 90 % interval (cm) | peak, cap 10,000 | peak, cap 5,000 | rank: default, 10,000, 5,000 |\n|---|---|---|---|---|---|---|")
for p, r in base.items():
    lo, hi = float(r["peak_life_lo"]), float(r["peak_life_hi"])
    interval = "periodic" if r["peak_periodic"] == "true" else f"[{100 * lo:.3f}, {100 * hi:.3f}]"
    print(f"| {r['mass_inner']} | {r['d']} | {100 * life[p]:.3f} | {interval} | {100 * float(caps[10000][p]['peak_amplitude_ideal']):.3f} | {100 * float(caps[5000][p]['peak_amplitude_ideal']):.3f} | {r['rank']}, {caps[10000][p]['rank']}, {caps[5000][p]['rank']} |")
print()
print(f"- `reduce` against `run` (showcase): {t['new_reduce'][0] / t['new_run'][0]:.3f}; (1,000 designs): {t['space_reduce'][0] / t['space_run'][0]:.3f}.")
print(f"- 1,000 designs: {e2e('space') / 60:.1f} min end to end on this machine, peak memory {max(t['space_run'][1], t['space_reduce'][1]):.0f} MiB (an overnight 10 h holds {36000 / e2e('space'):.0f} such studies).")
print()
m = max(race["motions"], 1)
print("**The race of the design life** (examples/race_cost: the showcase's nine ideal curves, the census passes once, then the lives measured both ways):\n")
print("| | periods | per motion that is not periodic | wall (s) |\n|---|---|---|---|")
print(f"| census (every start, both passes) | {race['census_periods']:,} | | |")
print(f"| life amplitudes by the race | {race['race_periods']:,} | {race['race_periods'] / m:,.0f} | {race['race_s']:.1f} |")
print(f"| every motion refined to the tolerance | {race['all_periods']:,} | {race['all_periods'] / m:,.0f} | {race['all_s']:.1f} |")
print()
print(f"{race['motions']} motions that are not periodic over {9 * 81} frequencies; the race spends {race['race_periods'] / max(race['all_periods'], 1):.1%} of the periods of refining all of them. Design peaks, race against all:")
print()
print("| m (kg) | d (m) | peak by the race (cm) | peak refining all (cm) |\n|---|---|---|---|")
for d in race["designs"]:
    print(f"| {d['m']} | {d['d']} | {100 * d['peak_race']:.4f} | {100 * d['peak_all']:.4f} |")
PYEOF
cat results/bench_forced_scale.md
