#!/usr/bin/env bash
# Regenerates assets/report.png, the README's picture of a report page: the design-space
# showcase (configs/design-space.toml) run and reduced into a temporary output root, copied
# elsewhere, checked in headless Chromium by tests/html_check.py (the browser test's checker),
# which then shows the zone map over e and d with the recommended design hovered and saves the
# window. Needs what scripts/test.sh installs: .venv (scripts/setup-python.sh) and Debian's
# chromium + chromium-driver. IMPACTSWEEP_BIN names the binary to use (default: a release build).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup-python.sh
if [ -n "${IMPACTSWEEP_BIN:-}" ]; then
  BIN=$IMPACTSWEEP_BIN
else
  cargo build --release --quiet
  BIN=target/release/impactsweep
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$BIN" run configs/design-space.toml --out "$tmp/out" --reduce --quiet
cp -r "$tmp/out" "$tmp/copy"
.venv/bin/python tests/html_check.py "$tmp/copy" --screenshot assets/report.png --shot-study design-space >/dev/null
echo "wrote assets/report.png"
