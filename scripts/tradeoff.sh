#!/usr/bin/env bash
# Regenerates results/tradeoff/: every solver's knob ladder on the paper system (impactsweep
# tradeoff) and the SciPy peer (scripts/peer_scipy.py), timed in the same script run on this
# machine, merged into one table (tradeoff.md, tradeoff.parquet) and one chart (tradeoff.svg/png).
# machine.txt records where and when it ran.
set -euo pipefail
cd "$(dirname "$0")/.."
out=results/tradeoff
PY="${IMPACTSWEEP_PYTHON:-$PWD/.venv/bin/python}"
if [ ! -x "$PY" ]; then
    scripts/setup-python.sh
    PY="$PWD/.venv/bin/python"
fi
mkdir -p "$out"
cargo build --release --quiet
{
    echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
    echo "cpu: $(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ //' || uname -m)"
    echo "cores: $(nproc 2>/dev/null || echo '?')"
    echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')"
    echo "os: $(uname -srm)"
    echo "rustc: $(rustc --version)"
    echo "python: $("$PY" -c 'import sys, scipy, numpy; print(sys.version.split()[0], "scipy", scipy.__version__, "numpy", numpy.__version__)')"
} > "$out/machine.txt"
"$PY" scripts/peer_scipy.py --out "$out/peer_scipy.json"
target/release/impactsweep tradeoff --out "$out" --peer "$out/peer_scipy.json"
echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')" >> "$out/machine.txt"
