#!/usr/bin/env bash
# Subset simulation at a stripe of an intensity measure against a truth
# (results/subset_stripe_validation.md). The seismic showcase's structure (configs/seismic.toml's
# M, K, C, e and Clough-Penzien load) under Sa(T1) stripes, the limit max |x| > 1.4 cm, two
# designs (m = 0 and m = 0.1 kg, d = 2 cm), at the 0.2-g stripe, where each motion is scaled so
# that its own Sa(T1) is 0.2 g:
# - the truth: Monte Carlo over TRUTH_N motions a design (default 400,000), its share that passed
#   with its Clopper-Pearson 95 % interval;
# - the estimates: the same study with 100 motions a design at study seeds 1 to SEEDS (default
#   40): fewer than 10 pass, so `reduce` takes p_f by subset simulation (1,000 samples a level),
#   each sample's motion scaled to the stripe as the sweep scales its realizations.
# Before stop 100 subset simulation ran the motions at their own level (S0) instead: on this
# study it read p_f = 1.00 where the truth is 7.1e-4.
# The raw numbers go to results/subset_stripe_validation/ (truth.csv, estimates.csv, run.txt);
# the report is the ratio of each estimate to the truth and its interval's coverage. `--report`
# rewrites it from those files alone; `--check` (CI) rewrites it to a temporary file, which must
# be the committed report byte for byte, and reruns seed 1, which must be its committed rows bit
# for bit (about a second in the test build).
#
#   scripts/subset_stripe_validation.sh            (about 9 minutes on 2 cores, release build:
#                                                   the truth 8 of them)
#   TRUTH_FROM=path/truth.csv scripts/subset_stripe_validation.sh   (the estimates alone)
#   scripts/subset_stripe_validation.sh --report | --check
set -euo pipefail
cd "$(dirname "$0")/.."
TRUTH_N=${TRUTH_N:-400000}
SEEDS=${SEEDS:-40}
TRUTH_FROM=${TRUTH_FROM:-}
out=results/subset_stripe_validation.md
data=results/subset_stripe_validation
mode=run
case "${1:-}" in
    --report) mode=report ;;
    --check) mode=check ;;
esac
if [ "$mode" != report ]; then
    if [ -n "${IMPACTSWEEP_BIN:-}" ]; then
        BIN=$IMPACTSWEEP_BIN
    else
        cargo build --quiet --release --bin impactsweep
        BIN=target/release/impactsweep
    fi
    WORK=$(mktemp -d)
    trap 'rm -rf "$WORK"' EXIT
fi
study() { # name seed realizations
    cat > "$WORK/$1.toml" <<TOML
[study]
name = "$1"
seed = $2

[system]
M = 1.0
K = 246.7
C = 0.628
e = 0.6

[scene]
kind = "random"
input = "base"
spectrum = "clough-penzien"
S0 = 0.005
intensity = "sa"
threshold = 0.014
realizations = $3

[sweep]
im = [0.2]
m = [0.0, 0.1]
d = [0.02]
TOML
    "$BIN" run "$WORK/$1.toml" --out "$WORK" --quiet
    "$BIN" reduce "$WORK/$1" > /dev/null
}
# Each design's row of a study's summary: m, then the columns below (the seed first when given).
rows() { # summary.csv [seed]
    python3 - "$@" <<'PY'
import csv, sys
keys = ("p_f", "p_f_lo", "p_f_hi", "p_f_method", "n_exceed", "n", "subset_runs")
for r in csv.DictReader(open(sys.argv[1])):
    print(",".join(sys.argv[2:3] + [r["mass_inner"]] + [r[k] for k in keys]))
PY
}
header="seed,m,p_f,p_f_lo,p_f_hi,p_f_method,n_exceed,n,subset_runs"
if [ "$mode" = check ]; then
    study seed_1 1 100
    got=$(rows "$WORK/seed_1/summary.csv" 1)
    want=$(grep '^1,' "$data/estimates.csv")
    if [ "$got" != "$want" ]; then
        echo "subset_stripe_validation --check: the estimates at seed 1 moved:" >&2
        echo "  committed $want" >&2
        echo "  now       $got" >&2
        exit 1
    fi
    committed=$out
    out=$WORK/report.md
fi
if [ "$mode" = run ]; then
    mkdir -p "$data"
    start=$(date +%s)
    if [ -n "$TRUTH_FROM" ]; then
        cp "$TRUTH_FROM" "$WORK/truth.csv"
    else
        study truth 7 "$TRUTH_N"
        echo "${header#seed,}" > "$WORK/truth.csv"
        rows "$WORK/truth/summary.csv" >> "$WORK/truth.csv"
    fi
    echo "$header" > "$WORK/estimates.csv"
    for s in $(seq 1 "$SEEDS"); do
        study "seed_$s" "$s" 100
        rows "$WORK/seed_$s/summary.csv" "$s" >> "$WORK/estimates.csv"
    done
    elapsed=$(( $(date +%s) - start ))
    echo "# scripts/subset_stripe_validation.sh: $elapsed s of wall time for the runs; $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); TRUTH_N=$TRUTH_N SEEDS=$SEEDS${TRUTH_FROM:+ (the truth reused from an earlier run)}" \
        > "$data/run.txt"
    mv "$WORK/truth.csv" "$WORK/estimates.csv" "$data"/
fi
python3 - "$data" > "$out.tmp" <<'PY'
import csv, statistics, sys

data = sys.argv[1]
run = open(f"{data}/run.txt").read().strip().lstrip("# ")
truth = {r["m"]: r for r in csv.DictReader(open(f"{data}/truth.csv"))}
est = list(csv.DictReader(open(f"{data}/estimates.csv")))
seeds = len({e["seed"] for e in est})
print("# Subset simulation at a stripe against a truth")
print()
print(f"`scripts/subset_stripe_validation.sh` ({run}), the raw numbers in `{data}/`.")
print("The seismic showcase's structure and load, each motion scaled so that its own Sa(T1) is")
print("0.2 g, the limit max |x| > 1.4 cm. **Truth**: Monte Carlo over every motion of a study of")
print(f"{int(next(iter(truth.values()))['n']):,} motions a design, with its Clopper-Pearson 95 % interval. "
      f"**Estimates**: the same study with")
print(f"100 motions a design at study seeds 1 to {seeds}, where fewer than 10 pass and `reduce` takes")
print("`p_f` by subset simulation (1,000 samples a level), with its stated 95 % interval.")
print()
print("| design | truth p_f [95 %] | estimates by subset simulation | ratio to truth: mean | median | sd | range | interval covers the truth | runs a seed |")
print("|---|---|---|---|---|---|---|---|---|")
for m, t in truth.items():
    p = float(t["p_f"])
    rows = [e for e in est if e["m"] == m]
    sub = [e for e in rows if e["p_f_method"] == "subset"]
    r = [float(e["p_f"]) / p for e in sub]
    cover = sum(1 for e in sub if float(e["p_f_lo"]) <= p <= float(e["p_f_hi"]))
    runs = statistics.median(int(e["subset_runs"]) for e in sub) if sub else 0
    print(f"| m = {m} kg, d = 0.02 m | {p:.3g} [{float(t['p_f_lo']):.3g}, {float(t['p_f_hi']):.3g}] "
          f"({t['n_exceed']} of {int(t['n']):,}) | {len(sub)} of {len(rows)} seeds | "
          f"{statistics.mean(r):.3f} | {statistics.median(r):.3f} | {statistics.stdev(r):.3f} | "
          f"{min(r):.2f}-{max(r):.2f} | {cover} of {len(sub)} | {runs:.0f} |")
PY
mv "$out.tmp" "$out"
if [ "$mode" = check ]; then
    if ! diff -u "$committed" "$out" >&2; then
        echo "subset_stripe_validation --check: $committed does not regenerate from $data/" >&2
        exit 1
    fi
    echo "subset_stripe_validation --check: the report regenerates, and seed 1 is its committed rows"
    exit 0
fi
cat "$out"
