#!/usr/bin/env bash
# Round trip client -> server -> client at 1 kHz on loopback (lockstep server,
# scripted client holding still), inside a private network namespace:
#   scripts/rtt_bench.sh [SECONDS] [--busy]
# --busy keeps the other core busy with a spinning process meanwhile.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
busy=${2:-}
if [[ "${IGMS_IN_NETNS:-}" != "1" ]]; then exec scripts/netns_run.sh "$0" "$@"; fi
url="udpm://239.255.76.67:7790?ttl=0"
build/server/igms-server --scene scenes/puma_wall.yaml --clock lockstep --lcm-url "$url" --quiet &
server=$!
spinner=""
if [[ "$busy" == "--busy" ]]; then
  (while :; do :; done) &
  spinner=$!
fi
trap 'kill $server ${spinner} 2>/dev/null || true' EXIT
sleep 0.5
build/haptic_client/igms-haptic --scene scenes/puma_wall.yaml --device scripted:scenes/idle_device.yaml \
  --lcm-url "$url" --duration "$seconds"
