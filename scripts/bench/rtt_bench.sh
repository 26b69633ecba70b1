#!/usr/bin/env bash
# Round trip client -> server -> client at 1 kHz on loopback (lockstep server,
# scripted client holding still), inside a private network namespace:
#   scripts/bench/rtt_bench.sh [SECONDS] [--busy]
# --busy keeps the other core busy with a spinning process meanwhile.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-60}
busy=${2:-}
source scripts/lib/session.sh
igms_in_netns "$0" "$@"
url="udpm://239.255.76.67:7790?ttl=0"
igms_start_server scenes/puma_wall.yaml "$url" --clock lockstep --quiet
if [[ "$busy" == "--busy" ]]; then
  (while :; do :; done) &
  igms_pids+=($!)  # stopped with the server
fi
sleep 0.2
igms_run_client scenes/puma_wall.yaml scripted:scenes/idle_device.yaml "$url" --duration "$seconds"
