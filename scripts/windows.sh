#!/usr/bin/env bash
# The station on Windows, built and checked on Linux (issue 46):
#   bash scripts/windows.sh            # cross-build telerehab.exe (x86_64-pc-windows-gnu, debug),
#                                      # run it under Wine: --version, a simulated session, and
#                                      # replays across the two systems
#   bash scripts/windows.sh --release  # the same with a release build
#   bash scripts/windows.sh --exe PATH # a telerehab.exe built already (scripts/windows_ci.sh)
#   TELEREHAB_BIN=target/debug/telerehab bash scripts/windows.sh   # a Linux binary built already
# Each system must reproduce its own simulated session bit for bit (`telerehab replay`: every
# recorded output compared); across the two, the replays say where they first differ (the
# platforms' C maths libraries round sin, exp, atan2 … differently in the last bit: BENCHMARKS.md,
# "The station on Windows"). Installs what it needs when missing (mingw-w64, wine64, the Rust
# target); runs Wine in a throwaway prefix, nothing is left. CI runs it through
# scripts/windows_ci.sh (with the unit tests under Wine and the installer).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT="$PWD"
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi

PROFILE=debug
FLAGS=()
EXE=""
case "${1:-}" in
  --release) PROFILE=release; FLAGS=(--release) ;;
  --exe) EXE="${2:?--exe needs the path of a telerehab.exe}" ;;
  "") ;;
  -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
  *) echo "windows.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
esac
TARGET=x86_64-pc-windows-gnu
TARGET_DIR="${CARGO_TARGET_DIR:-$ROOT/target}"
step() { printf '\n== windows: %s\n' "$*"; }
fail() { echo "windows.sh: FAILED: $*" >&2; exit 1; }

if ! command -v x86_64-w64-mingw32-gcc >/dev/null 2>&1 || ! command -v wine >/dev/null 2>&1; then
  step "install mingw-w64 and wine64"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO=sudo
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q mingw-w64 wine64 >/dev/null
fi
rustup target list --installed | grep -qx "$TARGET" || rustup target add "$TARGET"

if [ -z "$EXE" ]; then
  step "build telerehab.exe ($PROFILE)"
  cargo build "${FLAGS[@]}" --target "$TARGET" -p telerehab
  EXE="$TARGET_DIR/$TARGET/$PROFILE/telerehab.exe"
fi
[ -f "$EXE" ] || fail "no telerehab.exe at $EXE"
# The Linux binary: TELEREHAB_BIN when given (as the browser tests take it), else built here.
LINUX="${TELEREHAB_BIN:-}"
if [ -z "$LINUX" ]; then
  cargo build "${FLAGS[@]}" -p telerehab
  LINUX="$TARGET_DIR/$PROFILE/telerehab"
fi
echo "telerehab.exe: $(du -k "$EXE" | cut -f1) kB"

WORK="$(mktemp -d)"
# shellcheck source=wine/prefix.sh
source scripts/wine/prefix.sh
cleanup() { wine_prefix_end; rm -rf "$WORK"; }
trap cleanup EXIT
step "a Wine prefix of its own"
wine_prefix "$WORK/wine" || fail "no Wine prefix"
wine() { command wine "$@" 2> >(grep -v '^[0-9a-f]*:fixme:' >&2); }

step "--version"
wine "$EXE" --version | tee "$WORK/version.txt"
grep -q '^telerehab ' "$WORK/version.txt" || fail "telerehab.exe --version says no version"

SESSION=(run --sim --headless --speed max --duration 10 --seed 7 --log warn)
step "a simulated session under Wine (10 s, seed 7)"
wine "$EXE" "${SESSION[@]}" --home 'Z:'"$WORK/home-win" --record 'Z:'"$WORK/win.mcap" \
  > "$WORK/win.txt" || { cat "$WORK/win.txt"; fail "the simulated session under Wine failed"; }
[ -s "$WORK/win.mcap" ] || fail "the session under Wine left no recording"

step "the same session on Linux"
"$LINUX" "${SESSION[@]}" --home "$WORK/home-linux" --record "$WORK/linux.mcap" > "$WORK/linux.txt"

step "each system reproduces its own session"
wine "$EXE" replay 'Z:'"$WORK/win.mcap" --log warn | tee "$WORK/replay-win-win.txt"
grep -q '^replay: identical' "$WORK/replay-win-win.txt" \
  || fail "Windows does not reproduce its own session bit for bit"
"$LINUX" replay "$WORK/linux.mcap" --log warn | tee "$WORK/replay-linux-linux.txt"
grep -q '^replay: identical' "$WORK/replay-linux-linux.txt" \
  || fail "Linux does not reproduce its own session bit for bit"

step "each system replays the other's session (says where they first differ)"
"$LINUX" replay "$WORK/win.mcap" --log warn 2>&1 | tail -1 || true
wine "$EXE" replay 'Z:'"$WORK/linux.mcap" --log warn 2>&1 | tail -1 || true

echo "windows.sh: telerehab.exe built and ran a simulated session under Wine; each system reproduces its own session bit for bit"
