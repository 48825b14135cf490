#!/usr/bin/env bash
# Issue 43's budget: the bundled frequency-response study (configs/frequency-response.toml) end
# to end (run, then reduce: the verification included) with this commit's binary and with the
# binary before the issue (BASE, default e7df294), in one script run, then one-frequency studies
# of chaotic points (16 starts, 1,000 h) with this commit's binary: `run` (the census and the
# design life) and `reduce` (the verification of the one design) timed apart.
# Writes results/bench_life_budget.md (figures, machine, load, commits) and prints it.
#
#   scripts/bench_life_budget.sh                 builds BASE in a worktree (target/base-BASE)
#   BASE_BIN=path/to/impactsweep scripts/bench_life_budget.sh
set -euo pipefail
cd "$(dirname "$0")/.."
base=${BASE:-e7df294}
work=$(mktemp -d)
trap 'git worktree remove --force "$work/base" 2>/dev/null || true; rm -rf "$work"' EXIT
cargo build --release --quiet
NEW=target/release/impactsweep
if [ -z "${BASE_BIN:-}" ]; then
  git worktree add --quiet --detach "$work/base" "$base"
  cargo build --release --quiet --manifest-path "$work/base/Cargo.toml" --target-dir "target/base-$base"
  BASE_BIN="target/base-$base/release/impactsweep"
fi
cfg=configs/frequency-response.toml
up0=$(uptime)
secs() { /usr/bin/time -f "%e" -o "$1" "${@:2}" >/dev/null; cat "$1"; }
# The trade a user can make: the race's cap a quarter of the default (the deciding designs are
# still measured to 1,024,000 periods by the verification).
sed -e 's/^design_peak = "worst"/design_peak = "worst"\nlife_max_periods = 256000/' "$cfg" > "$work/quarter.toml"
grep -q '^life_max_periods = 256000' "$work/quarter.toml"
for v in base new quarter; do
  bin=$NEW; study=$cfg
  [ "$v" = base ] && bin=$BASE_BIN
  [ "$v" = quarter ] && study=$work/quarter.toml
  run=$(secs "$work/t" "$bin" run "$study" --out "$work/$v" --quiet)
  red=$(secs "$work/t" "$bin" reduce "$work/$v/frequency-response")
  echo "$v $run $red" >> "$work/showcase"
done
# One-frequency studies: Table I's M and K, C = 0.1 N s/m, e = 0.9, F0 = 0.1 N, 16 starts, seed 1.
point() { # name m d r
  cat > "$work/$1.toml" <<TOML
[study]
name = "$1"
seed = 1
[system]
M = 0.1
K = 400.0
C = 0.1
e = 0.9
m = $2
d = $3
x0 = 0.0
v0 = 0.0
y0 = 0.0
w0 = 0.0
[scene]
kind = "harmonic"
F0 = 0.1
r = $4
starts = 16
TOML
  run=$(secs "$work/t" "$NEW" run "$work/$1.toml" --out "$work/one" --quiet)
  red=$(secs "$work/t" "$NEW" reduce "$work/one/$1")
  echo "| $1 | $(awk "BEGIN { print $2 * 1000 }") | $(awk "BEGIN { print $3 * 1000 }") | $4 | $run | $red |"
}
points=$(
  point P1 0.02 0.02 1.01
  point P2 0.005 0.005 0.975
  point S1 0.02 0.02 1.0
  point S2 0.005 0.02 0.99
  point S5 0.01 0.02 0.995
)
up1=$(uptime)
read -r _ brun bred < <(grep '^base' "$work/showcase")
read -r _ nrun nred < <(grep '^new' "$work/showcase")
read -r _ qrun qred < <(grep '^quarter' "$work/showcase")
# Each design's ideal peak and rank (summary.csv, columns by name).
ranks() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    { printf "%s:%.4f:%s ", $col["point"], 100 * $col["peak_amplitude_ideal"], $col["rank"] }' \
    "$work/$1/frequency-response/summary.csv"
}
# The race's periods in the showcase's ideal case (attractors.csv: the ideal case's rows).
race() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    $col["kind"] != "periodic" && $col["kind"] != "neutral" { n++; p += $col["measured_periods"] }
    END { printf "%d motions, %.3g periods", n, p }' "$work/$1/frequency-response/attractors.csv"
}
out=results/bench_life_budget.md
{
  echo "## Issue 43's budget (\`scripts/bench_life_budget.sh\`)"
  echo
  echo "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores," \
    "this commit \`$(git rev-parse --short HEAD)\` against \`$base\`, release builds, one run of each."
  echo "\`uptime\` at start: \`$up0\`; at end: \`$up1\`."
  echo
  echo "The bundled frequency-response study, wall seconds:"
  echo
  echo "| binary | run | reduce | end to end | ideal case (attractors.csv) |"
  echo "|---|---|---|---|---|"
  echo "| \`$base\` | $brun | $bred | $(awk "BEGIN { print $brun + $bred }") | $(race base) |"
  echo "| this commit | $nrun | $nred | $(awk "BEGIN { print $nrun + $nred }") | $(race new) |"
  echo "| this commit, \`life_max_periods = 256000\` | $qrun | $qred | $(awk "BEGIN { print $qrun + $qred }") | $(race quarter) |"
  echo
  echo "Ratios to \`$base\`: $(awk "BEGIN { printf \"%.2f\", ($nrun + $nred) / ($brun + $bred) }") by default," \
    "$(awk "BEGIN { printf \"%.2f\", ($qrun + $qred) / ($brun + $bred) }") with the quarter cap (the budget: 1.5)."
  echo
  echo "Each design's ideal peak (cm) and rank, \`point:peak:rank\`:"
  echo
  echo "- \`$base\`: $(ranks base)"
  echo "- this commit: $(ranks new)"
  echo "- quarter cap: $(ranks quarter)"
  echo
  echo "One-frequency studies (16 starts, 1,000 h, study seed 1), this commit, wall seconds:"
  echo "\`run\` is the census and the design life, \`reduce\` the verification of the one design."
  echo
  echo "| point | m (g) | d (mm) | r | run | reduce |"
  echo "|---|---|---|---|---|---|"
  echo "$points"
} > "$out"
cat "$out"
