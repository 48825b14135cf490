#!/usr/bin/env bash
# Issue 43's budget: the bundled frequency-response study (configs/frequency-response.toml) end
# to end (run, then reduce: the verification included) with this commit's binary and with the
# binary before the issue (BASE, default e7df294), in one script run (ROUNDS runs of each, default
# 3, interleaved; their medians, and each round's ratio), then one-frequency studies
# of chaotic points (16 starts, 1,000 h) with this commit's binary: `run` (the census and the
# design life) and `reduce` (a study of one design is not verified: no order to decide) timed apart.
# Writes results/bench_life_budget.md (figures, machine, load, commits) and prints it.
#
#   scripts/bench_life_budget.sh                 builds BASE in a worktree (target/base-BASE)
#   BASE_BIN=path/to/impactsweep scripts/bench_life_budget.sh
#   NEW_BIN=path/to/impactsweep ...              this commit's binary, built already
#   OUT=path.md ...                              the report elsewhere (default below);
#   BUILDS="..."                                 what the binaries are (default "release builds")
set -euo pipefail
cd "$(dirname "$0")/.."
base=${BASE:-e7df294}
work=$(mktemp -d)
trap 'git worktree remove --force "$work/base" 2>/dev/null || true; rm -rf "$work"' EXIT
# NEW_BIN: this commit's binary built already (e.g. into another target directory).
NEW=${NEW_BIN:-target/release/impactsweep}
[ -n "${NEW_BIN:-}" ] || cargo build --release --quiet
if [ -z "${BASE_BIN:-}" ]; then
  git worktree add --quiet --detach "$work/base" "$base"
  cargo build --release --quiet --manifest-path "$work/base/Cargo.toml" --target-dir "target/base-$base"
  BASE_BIN="target/base-$base/release/impactsweep"
fi
cfg=configs/frequency-response.toml
up0=$(uptime)
secs() { /usr/bin/time -f "%e" -o "$1" "${@:2}" >/dev/null; cat "$1"; }
secs2() { /usr/bin/time -f "%e %U" -o "$1" "${@:2}" >/dev/null; cat "$1"; }
# The trade a user can make: the race's cap a quarter of the default (the deciding designs are
# still measured to 1,024,000 periods by the verification).
sed -e 's/^design_peak = "worst"/design_peak = "worst"\nlife_max_periods = 256000/' "$cfg" > "$work/quarter.toml"
grep -q '^life_max_periods = 256000' "$work/quarter.toml"
# The base and this commit ROUNDS times each (default 3), interleaved, so a machine whose speed
# drifts during the script weighs on both alike; the quarter cap once. Each run in a fresh
# directory (an existing one would resume).
rounds=${ROUNDS:-3}
one() { # label binary study
  local run red
  run=$(secs "$work/t" "$2" run "$3" --out "$work/$1" --quiet)
  red=$(secs "$work/t" "$2" reduce "$work/$1/frequency-response")
  echo "$1 $run $red" >> "$work/showcase"
}
for k in $(seq "$rounds"); do
  one "base$k" "$BASE_BIN" "$cfg"
  one "new$k" "$NEW" "$cfg"
done
one quarter "$NEW" "$work/quarter.toml"
ln -s "$work/base1" "$work/base"
ln -s "$work/new1" "$work/new"
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
  # Three runs each (this machine's speed drifts within minutes); the median wall time, with
  # the CPU time of that run: CPU / wall near 2 is both cores busy.
  local k rows=""
  for k in 1 2 3; do
    rm -rf "$work/one"
    rows+="$(secs2 "$work/t" "$NEW" run "$work/$1.toml" --out "$work/one" --quiet)"
    rows+=" $(secs2 "$work/t" "$NEW" reduce "$work/one/$1")"$'\n'
  done
  local run red
  run=$(sort -g -k1,1 <<< "${rows%$'\n'}" | awk 'NR == 2 { printf "%s (CPU %s)", $1, $2 }')
  red=$(sort -g -k3,3 <<< "${rows%$'\n'}" | awk 'NR == 2 { printf "%s (CPU %s)", $3, $4 }')
  echo "| $1 | $(awk "BEGIN { print $2 * 1000 }") | $(awk "BEGIN { print $3 * 1000 }") | $4 | $run | $red |"
}
points=$(
  point P1 0.02 0.02 1.01
  point P2 0.005 0.005 0.975
  point S1 0.02 0.02 1.0
  point S2 0.005 0.02 0.99
  point S5 0.01 0.02 0.995
  point S3 0.01 0.02 0.935
  point S4 0.02 0.01 0.9
)
up1=$(uptime)
# Medians over the rounds of run, reduce and end to end; the end-to-end times in round order.
# The median; of an even count, the mean of the middle two (the lower alone read 1.79x where
# the two rounds gave 1.79 and 1.56).
med() { sort -g | awk '{ a[NR] = $1 } END { if (NR % 2) print a[(NR + 1) / 2]; else printf "%.2f\n", (a[NR / 2] + a[NR / 2 + 1]) / 2 }'; }
stat() { # label: median run, reduce, end to end, then every end to end
  local rows
  rows=$(grep "^$1[0-9]* " "$work/showcase")
  echo "$(awk '{ print $2 }' <<< "$rows" | med) $(awk '{ print $3 }' <<< "$rows" | med)" \
    "$(awk '{ print $2 + $3 }' <<< "$rows" | med) $(awk '{ printf "%s%.1f", (NR > 1 ? "/" : ""), $2 + $3 }' <<< "$rows")"
}
read -r brun bred btot ball < <(stat base)
read -r nrun nred ntot nall < <(stat new)
read -r qrun qred qtot qall < <(stat quarter)
# Each round's ratio (this commit's round k against the base's round k).
paired=$(paste -d' ' <(grep '^base' "$work/showcase") <(grep '^new' "$work/showcase") \
  | awk '{ printf "%s%.2f", (NR > 1 ? ", " : ""), ($5 + $6) / ($2 + $3) }')
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
out=${OUT:-results/bench_life_budget.md}
{
  echo "## Issue 43's budget (\`scripts/bench_life_budget.sh\`)"
  echo
  echo "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores," \
    "this commit \`$(git rev-parse --short HEAD)\` against \`$base\`, ${BUILDS:-release builds}, $rounds runs of each" \
    "interleaved (the quarter cap one)."
  echo "\`uptime\` at start: \`$up0\`; at end: \`$up1\`."
  echo
  echo "The bundled frequency-response study, wall seconds (medians over the runs; end to end of each run"
  echo "in the order run):"
  echo
  echo "| binary | run | reduce | end to end | each run | ideal case (attractors.csv) |"
  echo "|---|---|---|---|---|---|"
  echo "| \`$base\` | $brun | $bred | $btot | $ball | $(race base) |"
  echo "| this commit | $nrun | $nred | $ntot | $nall | $(race new) |"
  echo "| this commit, \`life_max_periods = 256000\` | $qrun | $qred | $qtot | $qall | $(race quarter) |"
  echo
  echo "Ratios to \`$base\`: $(awk "BEGIN { printf \"%.2f\", $ntot / $btot }") by default (the medians; each round's: $paired)," \
    "$(awk "BEGIN { printf \"%.2f\", $qtot / $btot }") with the quarter cap (the budget: 1.5)."
  echo
  echo "Each design's ideal peak (cm) and rank, \`point:peak:rank\`:"
  echo
  echo "- \`$base\`: $(ranks base)"
  echo "- this commit: $(ranks new)"
  echo "- quarter cap: $(ranks quarter)"
  echo
  echo "One-frequency studies (16 starts, 1,000 h, study seed 1), this commit, wall seconds, the median"
  echo "of three runs (with that run's CPU seconds, user time):"
  echo "\`run\` is the census and the design life, \`reduce\` the reduction (a study of one design has no ranking to verify)."
  echo
  echo "| point | m (g) | d (mm) | r | run | reduce |"
  echo "|---|---|---|---|---|---|"
  echo "$points"
} > "$out"
cat "$out"
