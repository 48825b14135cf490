#!/usr/bin/env bash
# The seismic decision's annual risk against a truth (results/risk_validation.md). For each design
# (m kg, d m) of configs/seismic.toml's scene and hazard:
# - the truth: P(f | Sa) measured directly at 40 stripes from 0.08 to 0.8 g (geometric), TRUTH_N
#   motions each (default 20,000), and lambda_f = int P(f | x) |d lambda(x)| over the power law,
#   the probit of P linear in ln x between the stripes (exact for a lognormal curve; 0 between
#   stripes where none passed, the last stripe's value above the last), with its binomial
#   standard error, and the same with P itself linear in ln x (the interpolation's check);
# - the estimates: the showcase's study of that design alone (six stripes of 1,000 motions,
#   capacities at the 0.2-g design stripe) at study seeds 1 to SEEDS (default 20): lambda_f as
#   the decision takes it (over the stripes' fitted lognormal where it holds, else the
#   capacities' curve that holds), lambda_f_capacities (the capacities' curve that holds) and
#   lambda_f_stripes (over the lognormal fitted to the stripes' counts), each with its 95 %
#   bootstrap interval over the motions.
# The raw numbers go to results/risk_validation/ (truth.csv: each stripe's share that passed;
# estimates.csv: each seed's three estimates with their intervals and the curve used); the report,
# results/risk_validation.md, is the ratio of each estimate to the truth (mean, standard
# deviation, range) and each interval's coverage. `--report` rewrites it from those files alone;
# `--check` (CI) rewrites it to a temporary file, which must be the committed report byte for
# byte, and reruns one estimate (m = 0.1 kg, d = 0.04 m, seed 1), which must be its committed
# row bit for bit (about 2 s in the test build).
#
# The same at fewer motions a stripe (the small-sample runs, results/risk_validation_n50.md and
# its kin): REALIZATIONS sets the seeds' motions a stripe, TRUTH_FROM reuses a measured truth.csv
# (run.txt names it), DATA and OUT the raw numbers' folder and the report; `--check` reads them
# the same way and reruns its one estimate at the run's REALIZATIONS.
#
#   scripts/risk_validation.sh [M D [M D ...]]    (default: 0.1 0.04, 0.2 0.02 and 0.0 0.01;
#                                                 about 15 minutes on 2 cores, dev build)
#   REALIZATIONS=50 SEEDS=40 TRUTH_FROM=results/risk_validation/truth.csv \
#       DATA=results/risk_validation_n50 OUT=results/risk_validation_n50.md scripts/risk_validation.sh
#   [DATA=… OUT=…] scripts/risk_validation.sh --report | --check
set -euo pipefail
cd "$(dirname "$0")/.."
TRUTH_N=${TRUTH_N:-20000}
SEEDS=${SEEDS:-20}
# Motions a stripe in each seed's study (the showcase's 1,000 by default).
REALIZATIONS=${REALIZATIONS:-1000}
# A truth.csv already measured for these designs (the truth does not depend on REALIZATIONS or
# SEEDS): reused instead of run again.
TRUTH_FROM=${TRUTH_FROM:-}
out=${OUT:-results/risk_validation.md}
data=${DATA:-results/risk_validation}
mode=run
case "${1:-}" in
    --report) mode=report ;;
    --check) mode=check ;;
esac
if [ "$mode" != report ]; then
    if [ -n "${IMPACTSWEEP_BIN:-}" ]; then
        BIN=$IMPACTSWEEP_BIN
    else
        cargo build --quiet --bin impactsweep
        BIN=target/debug/impactsweep
    fi
    WORK=$(mktemp -d)
    trap 'rm -rf "$WORK"' EXIT
fi
study() { # name m d seed realizations im design_intensity
    sed -e "s/^name = .*/name = \"$1\"/" -e "s/^seed = .*/seed = $4/" \
        -e "s/^realizations = .*/realizations = $5/" -e "s/^m = .*/m = [$2]/" \
        -e "s/^d = .*/d = [$3]/" -e "s/^im = .*/im = [$6]/" \
        -e "s/^design_intensity = .*/design_intensity = $7/" configs/seismic.toml > "$WORK/$1.toml"
    "$BIN" run "$WORK/$1.toml" --out "$WORK" --quiet
    "$BIN" reduce "$WORK/$1" > /dev/null
}
# The showcase's own stripes (g) and design stripe, at which each seed's study runs.
showcase_im="0.1, 0.15, 0.2, 0.25, 0.3, 0.4"
showcase_design=0.2
# A seed's estimates row: m, d, seed, then the study's summary columns.
estimate_row() { # summary.csv m d seed
    python3 - "$@" <<'PY'
import csv, sys
r = next(csv.DictReader(open(sys.argv[1])))
keys = ("lambda_f", "lambda_f_lo", "lambda_f_hi", "lambda_f_curve", "lambda_f_capacities",
        "lambda_f_capacities_lo", "lambda_f_capacities_hi", "lambda_f_stripes",
        "lambda_f_stripes_lo", "lambda_f_stripes_hi")
print(",".join(sys.argv[2:5] + [r[k] for k in keys]))
PY
}
if [ "$mode" = check ]; then
    # The committed run's motions a stripe (run.txt; 1,000 where it does not say).
    REALIZATIONS=$(sed -n 's/.*REALIZATIONS=\([0-9]*\).*/\1/p' "$data/run.txt")
    REALIZATIONS=${REALIZATIONS:-1000}
    study seed_0.1_0.04_1 0.1 0.04 1 "$REALIZATIONS" "$showcase_im" "$showcase_design"
    got=$(estimate_row "$WORK/seed_0.1_0.04_1/summary.csv" 0.1 0.04 1)
    want=$(grep '^0.1,0.04,1,' "$data/estimates.csv")
    if [ "$got" != "$want" ]; then
        echo "risk_validation --check: the estimate of m = 0.1, d = 0.04, seed 1 moved:" >&2
        echo "  committed $want" >&2
        echo "  now       $got" >&2
        exit 1
    fi
    committed=$out
    out=$WORK/report.md
fi
if [ "$mode" = run ]; then
    [ $# -gt 0 ] || set -- 0.1 0.04 0.2 0.02 0.0 0.01
    stripes=$(python3 -c "print(', '.join(repr(round(0.08 * 10 ** (i / 39), 6)) for i in range(40)))")
    design_im=$(python3 -c "print(round(0.08 * 10 ** (16 / 39), 6))")
    mkdir -p "$data"
    echo "m,d,im,p_f,n" > "$WORK/truth.csv"
    echo "m,d,seed,lambda_f,lambda_f_lo,lambda_f_hi,lambda_f_curve,lambda_f_capacities,lambda_f_capacities_lo,lambda_f_capacities_hi,lambda_f_stripes,lambda_f_stripes_lo,lambda_f_stripes_hi" \
        > "$WORK/estimates.csv"
    start=$(date +%s)
    while [ $# -ge 2 ]; do
        if [ -n "$TRUTH_FROM" ]; then
            grep -q "^$1,$2," "$TRUTH_FROM" ||
                { echo "risk_validation: $TRUTH_FROM has no truth for m = $1, d = $2" >&2; exit 2; }
        else
            study "truth_$1_$2" "$1" "$2" 2026 "$TRUTH_N" "$stripes" "$design_im"
            python3 - "$WORK/truth_$1_$2/fragility.csv" "$1" "$2" "$TRUTH_N" >> "$WORK/truth.csv" <<'PY'
import csv, sys
for r in csv.DictReader(open(sys.argv[1])):
    if r["p_f"]:
        print(f"{sys.argv[2]},{sys.argv[3]},{r['im']},{r['p_f']},{sys.argv[4]}")
PY
        fi
        for s in $(seq 1 "$SEEDS"); do
            study "seed_$1_$2_$s" "$1" "$2" "$s" "$REALIZATIONS" "$showcase_im" "$showcase_design"
            estimate_row "$WORK/seed_$1_$2_$s/summary.csv" "$1" "$2" "$s" >> "$WORK/estimates.csv"
        done
        shift 2
    done
    elapsed=$(( $(date +%s) - start ))
    echo "# scripts/risk_validation.sh: $elapsed s of wall time for the runs; $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); TRUTH_N=$TRUTH_N SEEDS=$SEEDS REALIZATIONS=$REALIZATIONS${TRUTH_FROM:+ TRUTH_FROM=$TRUTH_FROM}" \
        > "$data/run.txt"
    mv "$WORK/estimates.csv" "$data"/
    [ -n "$TRUTH_FROM" ] || mv "$WORK/truth.csv" "$data"/
fi
python3 - "$data" > "$out.tmp" <<'PY'
import csv, math, statistics, sys
from statistics import NormalDist

data = sys.argv[1]
run = open(f"{data}/run.txt").read().strip().lstrip("# ")
# Motions a stripe in each seed's study (run.txt says so since it could differ from 1,000).
motions = int(run.split("REALIZATIONS=")[1].split()[0]) if "REALIZATIONS=" in run else 1000
K0, K = 3.72e-4, 2.5
N01 = NormalDist()
# The committed numbers were run over configs/seismic.toml's power law: refuse to integrate them
# over another.
try:
    import tomllib

    hz = tomllib.load(open("configs/seismic.toml", "rb"))["hazard"]
    if (hz.get("k0"), hz.get("k")) != (K0, K):
        sys.exit(f"risk_validation: these numbers are over the hazard k0 = {K0}, k = {K}; "
                 f"configs/seismic.toml now has k0 = {hz.get('k0')}, k = {hz.get('k')}: "
                 "run the script again with K0, K here set to them")
except ImportError:  # Python before 3.11: no check
    pass

def rate(x):
    return K0 * x ** -K

def num(v):
    try:
        return float(v)
    except ValueError:
        return float("nan")

# The truth: this run's own, or the one it reused (run.txt's TRUTH_FROM).
truth_csv = run.split("TRUTH_FROM=")[1].split()[0] if "TRUTH_FROM=" in run else f"{data}/truth.csv"
truth_rows = list(csv.DictReader(open(truth_csv)))
estimates = list(csv.DictReader(open(f"{data}/estimates.csv")))
designs = list(dict.fromkeys((r["m"], r["d"]) for r in truth_rows))

def integral(x, curve):
    """int P |d lambda| over the stripes' span, P(u) = curve(i, t) on [x_i, x_i+1] (u = ln x,
    t in [0, 1]), by Simpson on 64 panels an interval, plus P at the last stripe times its rate."""
    total = 0.0
    for i in range(len(x) - 1):
        u0, u1 = math.log(x[i]), math.log(x[i + 1])
        m, h = 64, (math.log(x[i + 1]) - math.log(x[i])) / 64
        for j in range(m + 1):
            u = u0 + j * h
            c = 1 if j in (0, m) else (4 if j % 2 else 2)
            total += c * h / 3 * K * K0 * math.exp(-K * u) * curve(i, (u - u0) / (u1 - u0))
    return total

def truth(m, d):
    xs = sorted((float(r["im"]), float(r["p_f"]), int(r["n"])) for r in truth_rows if (r["m"], r["d"]) == (m, d))
    x, p, n = [a[0] for a in xs], [a[1] for a in xs], [a[2] for a in xs]
    last = p[-1] * rate(x[-1])
    # The probit of P linear in ln x (exact for a lognormal curve); 0 where neither end passed.
    z = [N01.inv_cdf(min(max(pi, 0.5 / ni), 1 - 0.5 / ni)) for pi, ni in zip(p, n)]
    def probit(i, t):
        if p[i] == 0 and p[i + 1] == 0:
            return 0.0
        return N01.cdf(z[i] + t * (z[i + 1] - z[i]))
    lam = integral(x, probit) + last
    lin = integral(x, lambda i, t: p[i] + t * (p[i + 1] - p[i])) + last
    # Binomial standard error through the weights of P linear in ln x.
    w = []
    for k in range(len(x)):
        e = [0.0] * len(x)
        e[k] = 1.0
        w.append(integral(x, lambda i, t, e=e: e[i] + t * (e[i + 1] - e[i])) + (rate(x[-1]) if k == len(x) - 1 else 0.0))
    se = math.sqrt(sum(wk * wk * pk * (1 - pk) / nk for wk, pk, nk in zip(w, p, n)))
    return lam, lin, se, p[0], p[-1], len(x), n[0]

first = truth(*designs[0])
seeds = len([e for e in estimates if (e["m"], e["d"]) == designs[0]])
print("# The seismic decision's annual risk against a truth")
print()
print(f"`scripts/risk_validation.sh` ({run}), the raw numbers in `{data}/`.")
print("`configs/seismic.toml`'s scene and hazard (`lambda(x) = 3.72e-4 x^-2.5`), one design a study.")
print(f"**Truth**: `P(f | Sa(T1))` measured directly at {first[5]} stripes from 0.08 to 0.8 g (geometric),")
print(f"{first[6]:,} motions each, and `lambda_f = int P(f | x) |d lambda(x)|` with the probit of `P` linear in")
print("ln x between the stripes (exact for a lognormal curve; the last stripe's value above the last);")
print("its standard error is the stripes' binomial one, and `P` itself linear in ln x gives the")
print("interpolation's check.")
print(f"**Estimates**: the showcase's study of that design alone (six stripes of {motions:,} motions,")
print(f"capacities at the 0.2-g design stripe) at study seeds 1 to {seeds}: `lambda_f` as the decision")
print("takes it (over the stripes' fitted lognormal where it holds, else the capacities' curve that")
print("holds; the curves it took are named), `lambda_f_capacities` (over the capacities' curve that")
print("holds) and `lambda_f_stripes` (over the lognormal fitted to the six stripes' counts), each")
print("with its 95 % bootstrap interval over the motions.")
print()
print("| design | truth `lambda_f` (SE) | with `P` linear | P at 0.08 / 0.8 g | estimate | ratio to truth: mean | sd | range | 95 % interval covers the truth |")
print("|---|---|---|---|---|---|---|---|---|")
for m, d in designs:
    lam, lin, se, p0, p1, _, _ = truth(m, d)
    est = [e for e in estimates if (e["m"], e["d"]) == (m, d)]
    for label, key in (("`lambda_f` (the decision)", "lambda_f"), ("`lambda_f_capacities`", "lambda_f_capacities"),
                       ("`lambda_f_stripes`", "lambda_f_stripes")):
        r = [num(e[key]) / lam for e in est]
        c = sum(1 for e in est if num(e[key + "_lo"]) <= lam <= num(e[key + "_hi"]))
        cover, curves = f"{c} of {len(est)}", ""
        if key == "lambda_f":
            used = [e["lambda_f_curve"] for e in est]
            curves = " (" + ", ".join(f"{c} {used.count(c)}" for c in sorted(set(used))) + ")"
        print(f"| m = {m} kg, d = {d} m | {lam:.5f} ({se:.5f}) | {lin:.5f} | {p0:.4f} / {p1:.4f} | {label}{curves} | "
              f"{statistics.mean(r):.4f} | {statistics.stdev(r) if len(r) > 1 else math.nan:.4f} | {min(r):.3f}-{max(r):.3f} | {cover} |")
PY
mv "$out.tmp" "$out"
if [ "$mode" = check ]; then
    if ! diff -u "$committed" "$out" >&2; then
        echo "risk_validation --check: $committed does not regenerate from $data/" >&2
        exit 1
    fi
    echo "risk_validation --check: $committed regenerates, and m = 0.1, d = 0.04, seed 1 is its committed row"
    exit 0
fi
cat "$out"
