#!/usr/bin/env bash
# scripts/live.sh as the README shows it: it prints a device URL with a token
# and a watch-only URL on this machine's 127.0.0.1, and a headless Chromium
# opening the device URL there gets the live view through the bridge (its
# WebSocket carries frames). Exit 77 (skipped) without Chromium.
#   live_script_test.sh BUILD_DIR
set -euo pipefail
cd "$(dirname "$0")/../.."
command -v chromium >/dev/null || { echo "skipped: no Chromium"; exit 77; }
out=$(mktemp -d)
trap 'kill $live 2>/dev/null || true; wait $live 2>/dev/null || true; rm -rf "$out"' EXIT
IGMS_BUILD=$1 IGMS_LIVE_NO_SETUP=1 IGMS_LIVE_PORT=17893 IGMS_LIVE_VIEW_PORT=17894 \
  bash scripts/live.sh --seconds 20 > "$out/live.txt" 2>&1 &
live=$!
for _ in $(seq 100); do grep -q "watch only" "$out/live.txt" && break; sleep 0.1; done
cat "$out/live.txt"
device=$(sed -n 's/.*(your mouse is the device): //p' "$out/live.txt")
[[ $device == http://127.0.0.1:17893/#token=* ]] || { echo "FAIL: no device URL with a token"; exit 1; }
grep -q "watch only: *http://127.0.0.1:17894/" "$out/live.txt" || { echo "FAIL: no watch-only URL"; exit 1; }
# The file that holds the token, and its folder, are this user's alone.
modes="$(stat -c %a out/live) $(stat -c %a out/live/device.url)"
[[ $modes == "700 600" ]] || { echo "FAIL: out/live and device.url have modes $modes, not 700 600"; exit 1; }
timeout 60 chromium --headless --no-sandbox --use-gl=swiftshader --enable-unsafe-swiftshader --window-size=800,600 \
  --screenshot="$out/shot.png" --virtual-time-budget=4000 "$device" 2>/dev/null
status=$(curl -s http://127.0.0.1:17893/status.json)
echo "device page status: $status"
frames=$(sed -n 's/.*"frames_sent":\([0-9]*\).*/\1/p' <<<"$status")
states=$(sed -n 's/.*"states":\([0-9]*\).*/\1/p' <<<"$status")
((states > 500)) || { echo "FAIL: the web device saw $states states"; exit 1; }
((frames > 10)) || { echo "FAIL: only $frames frames reached the browser through the bridge"; exit 1; }
[[ -s "$out/shot.png" ]] || { echo "FAIL: no screenshot"; exit 1; }
echo "live_script_test: passed ($frames frames through the bridge)"
