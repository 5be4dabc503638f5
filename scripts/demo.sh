#!/usr/bin/env bash
# A whole simulated session on this machine, no hardware: a therapist hub on loopback, a
# 60 s patient session at 1 kHz recorded to out/session.mcap, and the hub's stored summaries.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi
cargo build --release -p station --bin telerehab
BIN=target/release/telerehab
mkdir -p out
"$BIN" therapist --listen 127.0.0.1:7878 --store out/therapist &
HUB=$!
trap 'kill -INT $HUB 2>/dev/null || true; wait $HUB 2>/dev/null || true' EXIT
sleep 0.5
"$BIN" run --sim --headless --duration "${DURATION:-60}" --seed 7 --exercise sine-road \
  --record out/session.mcap --therapist 127.0.0.1:7878
echo "therapist store:"; find out/therapist -type f | sort
