#!/usr/bin/env bash
# The whole test suite, from a fresh clone: installs what the tests need (pinned Python packages
# for the interop and browser tests, Debian's chromium + chromium-driver for the browser test and
# qemu-user for the processor test), checks formatting, lints and the docs' links, then runs every
# test: the Rust suite, then the Python package (python/) built and installed into .venv the way a
# user does (`pip install ./python`) and its pytest suite, compared against the binary just tested.
set -euo pipefail
cd "$(dirname "$0")/.."
# Each phase's start, in seconds since the script's (BENCHMARKS.md, "CI time", reads them).
phase() { echo "test.sh: [${SECONDS} s] $*" >&2; }
# The Python packages and the browser install only download and unpack: they run in the
# background while the Rust build below keeps both cores busy, and the script waits for them
# before the first test that needs them (BENCHMARKS.md, "CI time").
scripts/setup-python.sh &
python_setup=$!
# The browser test of the HTML pages (tests/html.rs) drives the system Chromium; the test of the
# build's processor level (tests/determinism.rs) runs the binary under QEMU's emulation of an
# older processor. Installed as root with apt-get when missing; elsewhere those tests say loudly
# that they skipped.
install_debian_packages() {
  local missing=()
  command -v chromium >/dev/null || missing+=(chromium)
  command -v chromedriver >/dev/null || missing+=(chromium-driver)
  command -v qemu-x86_64 >/dev/null || missing+=(qemu-user)
  if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
      echo "test.sh: installing ${missing[*]} with apt-get" >&2
      export DEBIAN_FRONTEND=noninteractive
      apt-get -o DPkg::Lock::Timeout=300 update -qq >&2
      apt-get -o DPkg::Lock::Timeout=300 install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
    else
      echo "test.sh: WARNING: ${missing[*]} missing and not installable here (not root or no apt-get): the browser test or the processor test will skip" >&2
    fi
  fi
}
install_debian_packages &
debian_setup=$!
export IMPACTSWEEP_PYTHON="$PWD/.venv/bin/python"
# A build from cold (CI's) gains nothing from incremental compilation's caches and pays for
# writing them (about 1 GB; the crate's cold test build 336 s -> 314 s without): off for every
# build below, the Python extension's too, so they share their artifacts (BENCHMARKS.md, "CI
# time").
export CARGO_INCREMENTAL=0
phase lint
cargo fmt --check
cargo clippy --all-targets -- -D warnings
# The library's docs, private items included (the module docs link to what they explain), with
# warnings denied: a link broken by a move or a rename fails here.
phase doc
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --lib --document-private-items
# Every test: the library's, the binary's, the integration tests and the benchmarks (each run
# once as a smoke test). The examples hold no tests; clippy above has compiled them, and
# building each at the test profile's opt-level would cost minutes (BENCHMARKS.md, "CI time").
phase test build
cargo test --lib --bins --tests --benches --no-run
wait "$python_setup"
wait "$debian_setup"
phase Rust tests
# Three test threads on two cores: the real Slurm cluster's test waits on the scheduler for
# most of its 36 s (6 s of CPU), and a third thread spends that wait (BENCHMARKS.md, "CI time").
# The variable, not `--test-threads`, which the benchmarks' harness (criterion) refuses.
RUST_TEST_THREADS=3 cargo test --lib --bins --tests --benches
# The committed validation of the design life (results/life_validation.md): its report
# regenerates from the committed estimates, and a slice of them (point P2, seeds 1 and 2) is
# reproduced bit for bit. The example in the test profile (its dependencies are built already).
phase validations
cargo build --quiet --profile test --example life_validation --example subset_validation \
  --example units_life_validation
LIFE_VALIDATION_BIN="$PWD/target/debug/examples/life_validation" scripts/life_validation.sh --check
# The committed validation of subset simulation (results/subset_validation.md): its report
# regenerates from the committed runs, and a slice (the exact Gaussian case's runs 0-2 at 1e-3,
# design A's run 0) is reproduced bit for bit.
SUBSET_VALIDATION_BIN="$PWD/target/debug/examples/subset_validation" scripts/subset_validation.sh --check
# The committed validation of the design life of several units
# (results/units_life_validation.md): its report regenerates from the committed runs, and a slice
# (point U2, study seed 1) is reproduced bit for bit.
UNITS_LIFE_VALIDATION_BIN="$PWD/target/debug/examples/units_life_validation" scripts/units_life_validation.sh --check
# The committed comparison of the whole curve with the default (results/life_curve.md): its
# report regenerates from the committed runs (tests/life.rs checks their claims).
scripts/life_curve.sh --check
# The committed validation of the seismic decision's annual risk (results/risk_validation.md),
# and the same at 200, 100 and 50 motions a stripe (results/risk_validation_n*.md): each report
# regenerates from its committed runs, and one estimate (m = 0.1 kg, d = 4 cm, study seed 1) is
# reproduced bit for bit by the binary just built.
IMPACTSWEEP_BIN="$PWD/target/debug/impactsweep" scripts/risk_validation.sh --check
for n in 200 100 50; do
  DATA=results/risk_validation_n$n OUT=results/risk_validation_n$n.md \
    IMPACTSWEEP_BIN="$PWD/target/debug/impactsweep" scripts/risk_validation.sh --check
done
# The committed validation of subset simulation at a stripe (results/subset_stripe_validation.md):
# its report regenerates from the committed runs, and seed 1's estimates are reproduced bit for
# bit.
IMPACTSWEEP_BIN="$PWD/target/debug/impactsweep" scripts/subset_stripe_validation.sh --check
# The Python extension (python/, a member of the workspace that `cargo test` leaves out): its
# lint, and its build (the dev profile, whose settings for the main crate and its dependencies
# are the test profile's) with the feature `share-test-build`, which resolves
# every dependency it shares with the main crate to the same features as the test build above
# (python/Cargo.toml), so the main crate and its dependencies are not compiled again: only pyo3,
# the pyarrow bridge and the extension itself are (BENCHMARKS.md, "CI time").
phase Python extension
cargo fmt --check --manifest-path python/Cargo.toml
cargo clippy -p impactsweep-py --all-targets --features share-test-build -- -D warnings
# maturin (pinned in .venv) builds it; the venv on PATH is where its pip hook finds the binary.
# The bits it computes do not depend on the profile (a user's `pip install ./python` builds
# release).
PATH="$PWD/.venv/bin:$PATH" MATURIN_PEP517_ARGS="--profile dev --features share-test-build" \
  .venv/bin/pip install --quiet --disable-pip-version-check --no-build-isolation ./python
phase pytest
IMPACTSWEEP_BIN="$PWD/target/debug/impactsweep" .venv/bin/python -m pytest python/tests -q -n 2
phase done
