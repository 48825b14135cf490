#!/usr/bin/env bash
# Issue 12's speed figures for the forced (harmonic) scene, in one script run on this machine:
#   1. examples/time_forced: impactsweep's cost per run and per forcing period, Table I system,
#      F0 = 0.3 N, r in {0.5, 0.8, 0.96, 0.98, 1.0, 1.2, 2.0}, with a fixed transient of N_TRANS
#      periods + 20 measured, and with the default transient (section convergence, cap 2000);
#   2. the SciPy peer (scripts/peer_scipy_forced.py: solve_ivp DOP853, rtol 1e-10, atol 1e-12,
#      the same forcing, wall events with a restart at each impact) on the fixed-transient runs;
#      the ratio is taken run by run, and the amplitudes are compared.
# Writes results/bench_forced.md (figures + machine + load) and prints it.
# Usage: scripts/bench_forced.sh [N_TRANS]   (default 300)
set -euo pipefail
cd "$(dirname "$0")/.."
PY="${IMPACTSWEEP_PYTHON:-$PWD/.venv/bin/python}"
[ -x "$PY" ] || { scripts/setup-python.sh; PY="$PWD/.venv/bin/python"; }
n_trans="${1:-300}"
out=results/bench_forced.md
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p results
uptime_start=$(uptime)
cargo run --release --quiet --example time_forced -- 7 5 "$n_trans" > "$work/rust.json"
for r in 0.5 0.8 0.96 0.98 1.0 1.2 2.0; do
  "$PY" scripts/peer_scipy_forced.py --F0 0.3 --r "$r" --n-trans "$n_trans" --n-meas 20 \
      --rtol 1e-10 --atol 1e-12 > "$work/peer_$r.json"
done
uptime_end=$(uptime)
"$PY" - "$work" "$n_trans" "$uptime_start" "$uptime_end" > "$out" <<'PYEOF'
import json, statistics, sys, subprocess, platform
work, n_trans, up0, up1 = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
rust = json.load(open(f"{work}/rust.json"))["runs"]
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), platform.machine())
commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
nproc = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
import glob, os
peers = {float(os.path.basename(f)[5:-5]): json.load(open(f)) for f in glob.glob(f"{work}/peer_*.json")}
fixed = [r for r in rust if r["fixed"]]
auto = [r for r in rust if not r["fixed"]]
print("## Forced scene (issue 12)\n")
print(f"`scripts/bench_forced.sh` on {cpu}, {nproc} cores, commit `{commit}`, release build, one core.")
print(f"`uptime` at start: `{up0.strip()}`; at end: `{up1.strip()}` (the machine is shared with other builders; load inflates every figure).\n")
print(f"Table I system, F0 = 0.3 N. Fixed transient: {n_trans} + 20 measured forcing periods for both impactsweep and SciPy "
      "(solve_ivp DOP853, rtol 1e-10, atol 1e-12, wall events, restart per impact, one call per forcing period). "
      "impactsweep times are medians of 7 batches of 5 runs.\n")
ratios = []
print("| r | impactsweep µs/run | µs/period | impacts/period | period | SciPy ms/run | ms/period | ratio | amplitude rel. diff |")
print("|---|---|---|---|---|---|---|---|---|")
for r in fixed:
    p = peers[float(r["r"])]
    per = r["seconds_per_run"]
    if p["outcome"] == "ok":
        ratio = p["wall_s"] / per
        ratios.append(ratio)
        diff = abs(p["amplitude"] - r["amplitude"]) / r["amplitude"]
        cells = f"{p['wall_s'] * 1e3:.0f} | {p['wall_s'] / p['periods'] * 1e3:.2f} | {ratio:.0f}x | {diff:.1e}"
    else:
        cells = f"{p['outcome']} | - | - | -"
    print(f"| {r['r']} | {per * 1e6:.0f} | {r['seconds_per_period'] * 1e6:.2f} | {r['impacts_per_period']:g} | {r['period']} | {cells} |")
print()
if ratios:
    print(f"Ratio SciPy / impactsweep: median **{statistics.median(ratios):.0f}x** (min {min(ratios):.0f}x, max {max(ratios):.0f}x). "
          "An amplitude difference far above 1e-7 marks a chaotic or not yet converged case, where two correct "
          "integrators part after a few periods (the orbit, not the transient, is comparable).\n")
print("Default transient (until the Poincaré section converges to 1e-10, at most 2000 periods):\n")
print("| r | µs/run | periods run | µs/period | outcome | period | impacts/period |")
print("|---|---|---|---|---|---|---|")
for r in auto:
    print(f"| {r['r']} | {r['seconds_per_run'] * 1e6:.0f} | {r['periods']} | {r['seconds_per_period'] * 1e6:.2f} | {r['outcome']} | {r['period']} | {r['impacts_per_period']:g} |")
PYEOF
cat "$out"
