#!/usr/bin/env bash
# Random realizations at half the cost (issue 69, item 5): the `run` command's CPU per
# realization of the seismic showcase's structure with a damper (configs/seismic.toml's scene,
# one design m = 0.1 kg, d = 1 cm), by the tool before (BASE_BIN) and after (NEW_BIN), rounds
# interleaved on one thread, and whether both wrote the same records byte for byte. Three
# studies of N realizations (default 20,000) each:
#   plain   the load as given (no intensity measure): one run a realization;
#   stripe  a 0.3-g stripe of Sa(T1) without a limit: the motion's own Sa, then its run at the
#           stripe;
#   design  the 0.2-g design stripe: own Sa, the run, and the capacity search's runs.
#   issue   the plain study with `threshold = 0.0099` m in place of the yield coefficient: what
#           the issue's base (`c6347dc`, which has neither Sa nor a yield coefficient) runs.
# STUDIES picks among them (default "plain stripe design"; "issue" against `c6347dc`).
# Prints a Markdown table (medians of ROUNDS, default 3, of user + system CPU, per realization)
# and the load before and after.
#
#   BASE_BIN=/path/to/old/impactsweep NEW_BIN=/path/to/new/impactsweep [STUDIES="…"] \
#       scripts/bench_random_speed.sh [N] [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/.."
N=${1:-20000}
ROUNDS=${2:-3}
: "${BASE_BIN:?BASE_BIN: the binary before}" "${NEW_BIN:?NEW_BIN: the binary after}"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
one_design() {
    sed -e "s/^name = \"seismic\"/name = \"$1\"/" -e "s/^realizations = .*/realizations = $N/" \
        -e 's/^m = .*/m = [0.1]/' -e 's/^d = .*/d = [0.01]/' configs/seismic.toml
}
one_design plain | sed -e '/^intensity = /d' -e '/^design_intensity = /d' -e '/^im = /d' \
    -e '/^\[hazard\]/,$d' > "$WORK/plain.toml"
one_design stripe | sed -e 's/^im = .*/im = [0.3]/' -e 's/^design_intensity = .*/design_intensity = 0.3/' \
    -e '/^yield_coefficient = /d' -e '/^\[hazard\]/,$d' > "$WORK/stripe.toml"
one_design design | sed -e 's/^im = .*/im = [0.2]/' > "$WORK/design.toml"
one_design issue | sed -e '/^intensity = /d' -e '/^design_intensity = /d' -e '/^im = /d' \
    -e 's/^yield_coefficient = .*/threshold = 0.0099/' -e '/^\[hazard\]/,$d' > "$WORK/issue.toml"
STUDIES=${STUDIES:-plain stripe design}
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); load before $(cut -d' ' -f1-3 /proc/loadavg)"
declare -A T
for r in $(seq 1 "$ROUNDS"); do
    for study in $STUDIES; do
        for side in base new; do
            bin=$BASE_BIN
            [ "$side" = new ] && bin=$NEW_BIN
            out=$WORK/out-$side-$r
            rm -rf "$out/$study"
            /usr/bin/time -f "%U %S" -o "$WORK/time" "$bin" run "$WORK/$study.toml" --out "$out" \
                --threads 1 --quiet
            T[$study,$side,$r]=$(awk '{ print $1 + $2 }' "$WORK/time")
        done
    done
done
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| study | before (us/realization) | after | after / before | same records |"
echo "|---|---|---|---|---|"
for study in $STUDIES; do
    med() { for r in $(seq 1 "$ROUNDS"); do echo "${T[$study,$1,$r]}"; done | sort -g |
        awk '{ a[NR] = $1 } END { print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2 }'; }
    b=$(med base)
    a=$(med new)
    same=yes
    files=0
    for f in "$WORK/out-base-1/$study"/*/*.parquet; do
        [ -e "$f" ] || continue
        files=$((files + 1))
        cmp -s "$f" "${f/out-base-1/out-new-1}" || same=no
    done
    [ "$files" -gt 0 ] || same="no files"
    awk -v s="$study" -v b="$b" -v a="$a" -v n="$N" -v same="$same" 'BEGIN {
        printf "| %s | %.1f | %.1f | %.3f | %s |\n", s, 1e6 * b / n, 1e6 * a / n, a / b, same }'
done
