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
source scripts/lib/session.sh
igms_in_netns "$0" "$@"
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
igms_start_logger "$out/session.lcmlog" "$url" -q --wait-session-s 5 \
  -c 'IGMS_(SESSION_INFO|HAPTIC_INPUT|ROBOT_STATE|SERVER_STATUS|CLIENT_STATUS)'
igms_start_server $scene "$url" --clock lockstep --quiet --save-edited "$out/edited_trajectory.yaml"
igms_run_client $scene "$device" "$url" --duration $seconds 2> "$out/client.log"
igms_stop_all
build/tools/igms-replay export "$out/session.lcmlog" "$out/export" 2>/dev/null
/usr/bin/python3 scripts/plot_session.py "$out/export" --out "$out" --title "$mode" >/dev/null
/usr/bin/python3 scripts/session_summary.py "$out" "$mode"
