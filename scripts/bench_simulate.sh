#!/usr/bin/env bash
# Issue 2's speed figures, in one script run on this machine:
#   1. criterion: `cargo bench --bench simulate` (Table I, e = 0.45..0.95, 51 two-peak runs);
#   2. examples/time_runs: the median time per run and per impact of the same 51 runs;
#   3. the SciPy peer (scripts/peer_scipy.py, DOP853 at rtol 1e-10 with wall events and a restart
#      at each impact) on the same runs; the ratio is taken run by run where the peer finishes.
# Writes results/bench_simulate.md (figures + machine) and prints it.
set -euo pipefail
cd "$(dirname "$0")/.."
PY="${IMPACTSWEEP_PYTHON:-$PWD/.venv/bin/python}"
[ -x "$PY" ] || { scripts/setup-python.sh; PY="$PWD/.venv/bin/python"; }
out=results/bench_simulate.md
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
cargo bench --bench simulate -- --warm-up-time 2 --measurement-time 5 2>/dev/null \
    | grep -E "^simulate|time:|thrpt:" | grep -v "%" > "$work/criterion.txt" || true
cargo run --release --quiet --example time_runs -- 21 200 > "$work/rust.json"
"$PY" scripts/peer_scipy.py --method DOP853 --reps 3 --json > "$work/peer.json"
load_end=$(cut -d' ' -f1-3 /proc/loadavg)
"$PY" - "$work/rust.json" "$work/peer.json" "$work/criterion.txt" "$load_start" "$load_end" > "$out" <<'PYEOF'
import json, statistics, sys, subprocess, platform
rust = json.load(open(sys.argv[1]))
peer = json.load(open(sys.argv[2]))["methods"][0]
crit = open(sys.argv[3]).read().strip()
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), platform.machine())
commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
rows, ratios = [], []
for r, p in zip(rust["runs"], peer["runs"]):
    assert abs(r["e"] - p["e"]) < 1e-9
    done = p["outcome"] != "chatter"
    ratio = p["wall_s"] / r["seconds_per_run"] if done else None
    if done:
        ratios.append(ratio)
    rows.append((r["e"], r["seconds_per_run"] * 1e6, r["impacts"], p["wall_s"] * 1e3, p["outcome"], p["impacts"], ratio))
print("## Simulator (issue 2)\n")
print(f"`scripts/bench_simulate.sh` on {cpu}, {subprocess.run(['nproc'], capture_output=True, text=True).stdout.strip()} cores, commit `{commit}`.")
print(f"Load average at start/end: {sys.argv[4]} / {sys.argv[5]} (other work on the machine inflates every figure).\n")
print(f"- impactsweep `exact` (tol 1e-12), one core: median **{rust['median_seconds_per_run'] * 1e6:.2f} µs per two-peak run**, "
      f"**{rust['median_seconds_per_impact'] * 1e9:.0f} ns per impact** (medians over the 51 runs of 21 batches of 200).")
print(f"- SciPy {peer['method']} (rtol {peer['rtol']:g}, atol {peer['atol']:g}), restart at each impact: "
      f"{len(ratios)} of {len(rows)} runs finish; {len(rows) - len(ratios)} are chatter cases it cannot get past "
      f"(guard: {peer['max_impacts']} impacts or {peer['budget_s']:g} s).")
if ratios:
    print(f"- Ratio SciPy / impactsweep on the finished runs: median **{statistics.median(ratios):.0f}x**, "
          f"min {min(ratios):.0f}x, max {max(ratios):.0f}x.\n")
print("Criterion (`cargo bench --bench simulate`, same run):\n\n```text\n" + crit + "\n```\n")
print("| e | impactsweep (µs/run) | impacts | SciPy DOP853 (ms/run) | SciPy outcome | SciPy impacts | ratio |")
print("|---|---|---|---|---|---|---|")
for e, us, imp, ms, out, pimp, ratio in rows:
    print(f"| {e:.2f} | {us:.2f} | {imp} | {ms:.2f} | {out} | {pimp} | {'-' if ratio is None else f'{ratio:.0f}x'} |")
PYEOF
cat "$out"
