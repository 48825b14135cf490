#!/usr/bin/env bash
# What the design life's first estimate costs, before any refinement: the showcase
# (configs/frequency-response.toml) end to end, in one script run,
#   1. with window peaks (`nonperiodic_peak = "window"`: no design life);
#   2. with `life_max_periods = 2000`: every motion that is not periodic measured once, for the
#      race's first 2,000 periods, and none refined (the floor of any design life that starts
#      from such a first estimate);
#   3. with the defaults (the race refines up to 20,000 periods per motion, to a 90 % interval
#      within 5 % of the estimate);
#   4. with `life_tol` 0.10 and 0.20: the tolerance a user can trade for time, with what it
#      does to the ideal design peaks and the ranks (against the defaults).
# The ideal case's motions and their measured periods come from each run's attractors.csv.
# Writes results/bench_life_floor.md (figures, machine, load, commit) and prints it.
#
#   scripts/bench_life_floor.sh
set -euo pipefail
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cargo build --release --quiet
BIN=target/release/impactsweep
cfg=configs/frequency-response.toml
sed -e 's/^design_peak = "worst"/design_peak = "worst"\nnonperiodic_peak = "window"/' "$cfg" \
  > "$work/window.toml"
sed -e 's/^design_peak = "worst"/design_peak = "worst"\nlife_max_periods = 2000/' "$cfg" \
  > "$work/first.toml"
cp "$cfg" "$work/default.toml"
for tol in 0.10 0.20; do
  sed -e "s/^design_peak = \"worst\"/design_peak = \"worst\"\nlife_tol = $tol/" "$cfg" \
    > "$work/tol$tol.toml"
  grep -q "^life_tol = $tol" "$work/tol$tol.toml"
done
grep -q '^nonperiodic_peak = "window"' "$work/window.toml"
grep -q '^life_max_periods = 2000' "$work/first.toml"
up0=$(uptime)
for v in window first default tol0.10 tol0.20; do
  /usr/bin/time -f "%e" -o "$work/$v.run" "$BIN" run "$work/$v.toml" --out "$work/$v" >/dev/null
  /usr/bin/time -f "%e" -o "$work/$v.reduce" "$BIN" reduce "$work/$v/frequency-response" >/dev/null
done
up1=$(uptime)
# motions that are not periodic in the ideal case, and the periods their statistics measured
motions() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    $col["kind"] != "periodic" && $col["kind"] != "neutral" { n++; p += $col["measured_periods"] }
    END { printf "%d | %d", n, p }' "$work/$1/frequency-response/attractors.csv"
}
# m, d, the ideal design peak (m) and the rank of each design (summary.csv, columns by name;
# its quoted cells come after these)
peaks() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    { print $col["mass_inner"] "," $col["d"] "," $col["peak_amplitude_ideal"] "," $col["rank"] }' \
    "$work/$1/frequency-response/summary.csv"
}
out=results/bench_life_floor.md
{
  echo "## The design life's floor (\`scripts/bench_life_floor.sh\`)"
  echo
  echo "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores," \
    "commit \`$(git rev-parse --short HEAD)\`, release build, one run of each."
  echo "\`uptime\` at start: \`$up0\`; at end: \`$up1\`."
  echo
  echo "| showcase | run (s) | reduce (s) | end to end (s) | ideal case: motions that are not periodic | their measured periods |"
  echo "|---|---|---|---|---|---|"
  for v in window first default tol0.10 tol0.20; do
    case $v in
      window) label='window peaks (`nonperiodic_peak = "window"`)' ;;
      first) label='first estimates only (`life_max_periods = 2000`)' ;;
      default) label='default (race, up to 20,000 periods, `life_tol = 0.05`)' ;;
      tol*) label="\`life_tol = ${v#tol}\`" ;;
    esac
    r=$(cat "$work/$v.run")
    d=$(cat "$work/$v.reduce")
    echo "| $label | $r | $d | $(echo "$r + $d" | bc) | $(motions "$v") |"
  done
  echo
  echo "The ideal design peaks (cm) and ranks, against the defaults:"
  echo
  echo "| m (kg) | d (m) | default | rank | life_tol 0.10 | rank | life_tol 0.20 | rank |"
  echo "|---|---|---|---|---|---|---|---|"
  paste -d, <(peaks default) <(peaks tol0.10) <(peaks tol0.20) |
    awk -F, '{ printf "| %s | %s | %.3f | %s | %.3f | %s | %.3f | %s |\n",
      $1, $2, 100 * $3, $4, 100 * $7, $8, 100 * $11, $12 }'
} > "$out"
cat "$out"
