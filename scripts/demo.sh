#!/usr/bin/env bash
# A whole simulated session on this machine, no hardware: a therapist hub on loopback, a
# 60 s patient session at 1 kHz recorded to out/session.mcap, and the hub's stored summaries.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi
cargo build --release -p telerehab
# The binary cargo just built, wherever the target directory is (CARGO_TARGET_DIR honoured).
BIN="${CARGO_TARGET_DIR:-$PWD/target}/release/telerehab"
mkdir -p out
# The station never overwrites a recording: this demo removes its own previous one.
rm -f out/session.mcap
# The hub picks a free port and says which on its first line.
"$BIN" therapist --listen 127.0.0.1:0 --store out/therapist > out/hub.log 2>&1 &
HUB=$!
trap 'kill -INT $HUB 2>/dev/null || true; wait $HUB 2>/dev/null || true' EXIT
ADDR=""
for _ in $(seq 100); do
  ADDR=$(sed -n 's/^listening on \([^ ]*\).*/\1/p' out/hub.log | head -n1)
  [ -n "$ADDR" ] && break
  kill -0 $HUB 2>/dev/null || { echo "the therapist hub did not start:"; cat out/hub.log; exit 1; }
  sleep 0.1
done
[ -n "$ADDR" ] || { echo "the therapist hub did not say where it listens"; exit 1; }
"$BIN" run --sim --headless --duration "${DURATION:-60}" --seed 7 --exercise sine-road \
  --record out/session.mcap --therapist "$ADDR"
echo "therapist hub log: out/hub.log; its store:"; find out/therapist -type f | sort
