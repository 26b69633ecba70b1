#!/usr/bin/env bash
# The logger under a real 1 kHz session on every igms channel (realtime
# server, scripted client holding still, logger recording everything):
#   scripts/logger_soak.sh [SECONDS]     (default 600: ten minutes)
# Prints the logger's counts; exits non-zero if anything was dropped.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ "${IGMS_IN_NETNS:-}" != "1" ]]; then exec scripts/netns_run.sh "$0" "$@"; fi
seconds=${1:-600}
url="udpm://239.255.76.67:7796?ttl=0"
dir=$(mktemp -d)
build/tools/igms-logger -o "$dir/soak.lcmlog" --lcm-url "$url" -q --stats-file "$dir/stats.json" &
logger=$!
sleep 0.3
build/server/igms-server --scene scenes/puma_wall.yaml --lcm-url "$url" --quiet &
server=$!
sleep 0.3
build/haptic_client/igms-haptic --scene scenes/puma_wall.yaml --device scripted:scenes/idle_device.yaml \
  --lcm-url "$url" --duration "$seconds" --quiet
kill "$server"; wait "$server" || true
sleep 0.5
kill "$logger"; wait "$logger" || true
cat "$dir/stats.json"
size=$(stat -c %s "$dir/soak.lcmlog")
echo "logger_soak: $seconds s, log $((size / 1048576)) MiB"
dropped=$(sed -n 's/.*"dropped": \([0-9]*\).*/\1/p' "$dir/stats.json")
rm -rf "$dir"
[[ "$dropped" == "0" ]]
