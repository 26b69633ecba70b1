#!/usr/bin/env bash
# One of the paper's experiments over the real bus (Son et al. 2003, section V),
# inside a private network namespace: igms-logger records, igms-server runs
# scenes/puma_obstacle.yaml in lockstep, igms-haptic plays the scripted device
# at 1 kHz; then everything stops and the session is exported, plotted and
# summarised.
#   scripts/paper_run.sh push|pull|nominal OUT_DIR
# OUT_DIR gets: session.lcmlog, edited_trajectory.yaml, export/ (CSV), the
# plots (joints, forces, path, snapshots; PNG and SVG), summary.json and summary.md.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:?push, pull or nominal}
out=${2:?output directory}
if [[ "${IGMS_IN_NETNS:-}" != "1" ]]; then exec scripts/netns_run.sh "$0" "$@"; fi
mkdir -p "$out"
out=$(cd "$out" && pwd)
url="udpm://239.255.76.67:${IGMS_PAPER_PORT:-7797}?ttl=0"
scene=scenes/puma_obstacle.yaml
seconds=7
case $mode in
  push) device=scripted:scenes/paper_push.yaml ;;
  pull) device=scripted:scenes/paper_pull.yaml ;;
  nominal) device=scripted:scenes/idle_device.yaml ;;
  *) echo "paper_run.sh: push, pull or nominal" >&2; exit 2 ;;
esac
rm -f "$out/session.lcmlog"
build/tools/igms-logger -o "$out/session.lcmlog" --lcm-url "$url" -q --wait-session-s 5 \
  -c 'IGMS_(SESSION_INFO|HAPTIC_INPUT|ROBOT_STATE|SERVER_STATUS|CLIENT_STATUS)' &
logger=$!
sleep 0.3
build/server/igms-server --scene $scene --clock lockstep --lcm-url "$url" --quiet \
  --save-edited "$out/edited_trajectory.yaml" &
server=$!
sleep 0.3
build/haptic_client/igms-haptic --scene $scene --device "$device" --lcm-url "$url" --duration $seconds \
  2> "$out/client.log"
kill "$server"; wait "$server" || true
sleep 0.3
kill "$logger"; wait "$logger" || true
build/tools/igms-replay export "$out/session.lcmlog" "$out/export" 2>/dev/null
/usr/bin/python3 scripts/plot_session.py "$out/export" --out "$out" --title "$mode" >/dev/null
/usr/bin/python3 scripts/session_summary.py "$out" "$mode"
