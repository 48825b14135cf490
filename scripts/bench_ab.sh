#!/usr/bin/env bash
# A change measured against the commit before it (a hot path that must keep every bit, or a
# census change that need not): the frequency-response showcase's
# `run` (the default study with the design life, and the same study with window peaks,
# `nonperiodic_peak = "window"`) by the tool at BASE (built here in a temporary worktree unless
# BASE_BIN names its binary) and by this one, ROUNDS times each, alternating (base, new, base,
# new, ...) so that a change of load falls on both. Prints each run's wall and user time, the
# medians and their ratio, and whether the two tools wrote the same datasets byte for byte
# (the points and attractors parts of the last round): a change meant to keep every bit
# shows that it did. Writes results/bench_ab.md (or OUT) and prints it.
#
#   scripts/bench_ab.sh BASE [ROUNDS]      (ROUNDS default 3)
#   OUT=results/bench_ab_x.md BASE_BIN=/path/to/impactsweep scripts/bench_ab.sh BASE
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
base="${1:?usage: scripts/bench_ab.sh BASE [ROUNDS]}"
rounds="${2:-3}"
out="${OUT:-results/bench_ab.md}"
work=$(mktemp -d)
cleanup() {
  git worktree remove --force "$work/base" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
cargo build --release --quiet
NEW="$ROOT/target/release/impactsweep"
if [ -z "${BASE_BIN:-}" ]; then
  git worktree add --quiet --detach "$work/base" "$base"
  (cd "$work/base" && CARGO_TARGET_DIR="$work/base-target" cargo build --release --quiet)
  BASE_BIN="$work/base-target/release/impactsweep"
fi
sed -e 's/^design_peak = "worst"/design_peak = "worst"\nnonperiodic_peak = "window"/' \
  configs/frequency-response.toml > "$work/window.toml"
grep -q '^nonperiodic_peak = "window"' "$work/window.toml"
cp configs/frequency-response.toml "$work/life.toml"
up0=$(uptime)
for study in window life; do
  for i in $(seq "$rounds"); do
    for tool in base new; do
      bin=$BASE_BIN
      [ "$tool" = new ] && bin=$NEW
      rm -rf "$work/out-$tool"
      /usr/bin/time -f "$study $tool $i %e %U" -a -o "$work/times" \
        "$bin" run "$work/$study.toml" --out "$work/out-$tool" >/dev/null 2>"$work/err" \
        || { cat "$work/err" >&2; exit 1; }
    done
  done
  for part in points attractors; do
    if cmp -s "$work/out-base/frequency-response/$part/part-000000.parquet" \
      "$work/out-new/frequency-response/$part/part-000000.parquet"; then
      echo "$study $part same" >>"$work/same"
    else
      echo "$study $part differ" >>"$work/same"
    fi
  done
done
up1=$(uptime)
head_commit=$(git rev-parse --short HEAD)
base_commit=$(git rev-parse --short "$base")
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')
python3 - "$work/times" "$work/same" "$rounds" "$cpu" "$(nproc)" "$head_commit" "$base_commit" \
  "$up0" "$up1" >"$out" <<'EOF'
import statistics, sys
times, same, rounds, cpu, cores, head, base, up0, up1 = sys.argv[1:]
rows = [l.split() for l in open(times) if l.strip()]
verdict = dict((f"{a} {b}", c) for a, b, c in (l.split() for l in open(same) if l.strip()))
print("## A change against its base (`scripts/bench_ab.sh`)\n")
print(f"{cpu}, {cores} cores; `{head}` against `{base}`; release builds; `impactsweep run` of the")
print(f"frequency-response showcase, {rounds} rounds, the two tools alternating.")
print(f"`uptime` at start: `{up0.strip()}`; at end: `{up1.strip()}`.\n")
print("| study | tool | wall (s), each round | median wall (s) | median user (s) |")
print("|---|---|---|---|---|")
med = {}
for study in ["window", "life"]:
    for tool in ["base", "new"]:
        r = [(float(w), float(u)) for s, t, _, w, u in rows if s == study and t == tool]
        mw = statistics.median(w for w, _ in r)
        mu = statistics.median(u for _, u in r)
        med[(study, tool)] = (mw, mu)
        walls = ", ".join(f"{w:.2f}" for w, _ in r)
        print(f"| {study} | {tool} | {walls} | {mw:.2f} | {mu:.2f} |")
print()
for study, name in [("window", "window peaks (no design life)"), ("life", "with the design life (the default)")]:
    (bw, bu), (nw, nu) = med[(study, "base")], med[(study, "new")]
    same_all = all(verdict[f"{study} {p}"] == "same" for p in ["points", "attractors"])
    bits = "the same datasets byte for byte" if same_all else "the datasets differ"
    print(f"- {name}: new / base = {nw / bw:.3f} wall, {nu / bu:.3f} user; {bits}.")
EOF
cat "$out"
