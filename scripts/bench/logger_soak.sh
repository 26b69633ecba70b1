#!/usr/bin/env bash
# The logger under a real 1 kHz session on every igms channel (realtime
# server, scripted client holding still, logger recording everything):
#   scripts/bench/logger_soak.sh [SECONDS]     (default 600: ten minutes)
# Prints the logger's counts; exits non-zero if anything was dropped.
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/lib/session.sh
igms_in_netns "$0" "$@"
seconds=${1:-600}
url="udpm://239.255.76.67:7796?ttl=0"
dir=$(mktemp -d)
igms_start_logger "$dir/soak.lcmlog" "$url" -q --stats-file "$dir/stats.json"
igms_start_server scenes/puma_wall.yaml "$url" --quiet
igms_run_client scenes/puma_wall.yaml scripted:scenes/idle_device.yaml "$url" --duration "$seconds" --quiet
igms_stop_all
cat "$dir/stats.json"
size=$(stat -c %s "$dir/soak.lcmlog")
echo "logger_soak: $seconds s, log $((size / 1048576)) MiB"
dropped=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))[\"dropped\"])" "$dir/stats.json")
rm -rf "$dir"
[[ "$dropped" == "0" ]]
