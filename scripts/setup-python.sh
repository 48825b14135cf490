#!/usr/bin/env bash
# Creates .venv with the pinned Python packages the tests and scripts use (PyPI only):
# pyarrow, DuckDB and polars read our Parquet in the interop tests; SciPy is the speed peer;
# Selenium drives the system Chromium (chromium-driver) in the browser test of the HTML pages;
# maturin builds the Python package (python/), pytest runs its tests (on both cores with
# pytest-xdist), and OpenTURNS and SALib run
# the reliability and sensitivity examples of docs/python.md, pyextremes its design-life one,
# eqsig the peer of the intensity measures (Sa, PGA).
# Idempotent: a venv that already has the pins is left alone.
set -euo pipefail
cd "$(dirname "$0")/.."
pins=(pyarrow==26.0.1 duckdb==2.0.0 polars==2.1.0 numpy==2.4.6 scipy==1.17.1 selenium==4.51.0
  maturin==1.16.0 pytest==9.2.0 pytest-xdist==3.8.0 openturns==1.27.post1 SALib==1.6.0
  pyextremes==2.6.1 pandas==3.1.1 eqsig==1.2.17)
stamp=.venv/.pins
if [ -x .venv/bin/python ] && [ -f "$stamp" ] && [ "$(cat "$stamp")" = "${pins[*]}" ]; then
  exit 0
fi
python3 -m venv .venv
.venv/bin/pip install --quiet --disable-pip-version-check "${pins[@]}"
echo "${pins[*]}" > "$stamp"
