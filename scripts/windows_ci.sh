#!/usr/bin/env bash
# The Windows station in CI (issue 46), in two halves around the Linux tests:
#   bash scripts/windows_ci.sh start LOGDIR    # cross-build, in the background, at the lowest
#                                              # CPU priority: telerehab.exe and the unit tests of
#                                              # the crates with Windows code (debug)
#   bash scripts/windows_ci.sh stop LOGDIR     # stop that build if it still runs (test.sh's exit)
#   bash scripts/windows_ci.sh finish LOGDIR   # wait for that build, then under Wine: the unit
#                                              # tests, a simulated session and its replays
#                                              # (scripts/windows.sh), the installer built from
#                                              # that telerehab.exe, installed, run and
#                                              # uninstalled silently (scripts/test_windows_installer.sh)
# Why in the background: the cross-build is CPU work of the order of the Linux build's, and the
# Linux end-to-end tests that run meanwhile mostly wait (real-time sessions, servers, browsers).
# At nice 19 the build takes only the CPU they leave (Linux gives a nice-0 task ~98 % of a
# contended core), so CI grows by what is left of the build when the tests end, not by all of it.
# The build has a target directory of its own (TARGET_DIR/windows-ci), so it never waits for the
# Linux build's lock. Each half prints how long it took; `finish` prints how long it waited.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT="$PWD"
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi

usage() { sed -n '2,12p' "$0"; exit 2; }
[ $# -eq 2 ] || usage
HALF="$1"
LOGS="$(cd "$2" && pwd)"
TARGET=x86_64-pc-windows-gnu
WIN_TARGET_DIR="${CARGO_TARGET_DIR:-$ROOT/target}/windows-ci"
BUILD_LOG="$LOGS/windows-build.log"
PID_FILE="$LOGS/windows-build.pid"
# The crates with Windows code of their own: the clock (waitable timer, MMCSS, timer period) and
# the wheel (DirectInput 8, and the safety chain both backends share).
UNIT_CRATES=(-p clock -p haptic-wheel -p wheel-devices)

# The workspace's debug profile as it is (dependencies at opt-level 1). At opt-level 0 the build
# is faster (412 s against 1 451 s here, under different loads) but the stripped telerehab.exe
# grows from 58 to 102 MB and its installer to 18.6 MB, too near the 20 MB a patient's download
# may be for package-windows.sh's check to stay meaningful.

build() {
  local t0=$EPOCHREALTIME
  echo "== windows build: $(date -u +%H:%M:%S) start"
  CARGO_TARGET_DIR="$WIN_TARGET_DIR" cargo build --target "$TARGET" -p telerehab
  CARGO_TARGET_DIR="$WIN_TARGET_DIR" cargo test --no-run --target "$TARGET" "${UNIT_CRATES[@]}" --lib
  awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { printf "== windows build: done in %.0f s\n", b - a }'
}

case "$HALF" in
  build) build ;;
  start)
    rustup target list --installed | grep -qx "$TARGET" \
      || { echo "windows_ci.sh: the Rust target $TARGET is missing (scripts/setup.sh adds it)" >&2; exit 1; }
    # A session of its own (so `stop` ends cargo, rustc and the linker together), at the lowest
    # CPU priority, which every process it starts inherits.
    setsid nice -n 19 bash "$0" build "$LOGS" > "$BUILD_LOG" 2>&1 < /dev/null &
    echo $! > "$PID_FILE"
    echo "== windows: cross-build started in the background (log: $BUILD_LOG)"
    ;;
  stop)
    if [ -f "$PID_FILE" ]; then
      kill -- -"$(cat "$PID_FILE")" 2>/dev/null || true
      rm -f "$PID_FILE"
    fi
    ;;
  finish)
    [ -f "$PID_FILE" ] || { echo "windows_ci.sh: no build was started (run 'start' first)" >&2; exit 1; }
    t0=$EPOCHREALTIME
    pid="$(cat "$PID_FILE")"
    # Not our child (start's shell has gone): wait by polling.
    while kill -0 "$pid" 2>/dev/null; do sleep 2; done
    rm -f "$PID_FILE"
    awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { printf "== windows: waited %.0f s for the cross-build\n", b - a }'
    if ! grep -q '^== windows build: done' "$BUILD_LOG"; then
      tail -n 60 "$BUILD_LOG"
      echo "windows_ci.sh: the cross-build failed (whole log: $BUILD_LOG)" >&2
      exit 1
    fi
    grep '^== windows build' "$BUILD_LOG"

    echo "== windows: unit tests under Wine (${UNIT_CRATES[*]})"
    # shellcheck source=wine/prefix.sh
    source scripts/wine/prefix.sh
    WORK="$(mktemp -d)"
    trap 'wine_prefix_end; rm -rf "$WORK"' EXIT
    wine_prefix "$WORK/wine"
    # DirectInput's cooperative level wants a window, so an X display.
    CARGO_TARGET_DIR="$WIN_TARGET_DIR" CARGO_TARGET_X86_64_PC_WINDOWS_GNU_RUNNER=wine \
      xvfb-run -a cargo test --target "$TARGET" "${UNIT_CRATES[@]}" --lib 2>&1 \
      | grep -v ':fixme:' | tee "$LOGS/windows-unit.log"
    python3 scripts/check_skips.py "$LOGS/windows-unit.log"
    wine_prefix_end

    echo "== windows: a simulated session, its replays on both systems"
    # The Linux binary the Linux tests ran (windows.sh would build one in its target otherwise).
    LINUX="${TELEREHAB_BIN:-${CARGO_TARGET_DIR:-$ROOT/target}/debug/telerehab}"
    EXE="$WIN_TARGET_DIR/$TARGET/debug/telerehab.exe"
    TELEREHAB_BIN="$LINUX" bash scripts/windows.sh --exe "$EXE"

    echo "== windows: the installer, installed, used and uninstalled silently"
    bash scripts/package-windows.sh --binary "$EXE" --out "$WORK/installer"
    bash scripts/test_windows_installer.sh "$WORK"/installer/telerehab-setup-*.exe
    awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { printf "== windows: finish took %.0f s\n", b - a }'
    ;;
  *) usage ;;
esac
