#!/usr/bin/env bash
# One session of any scene with a scripted device, over the real bus, inside a
# private network namespace: igms-logger records, igms-server runs the scene
# in lockstep, igms-haptic plays the device script at 1 kHz; then everything
# stops and the session is exported, plotted and summarised.
#   scripts/sessions/run_session.sh SCENE DEVICE_SCRIPT OUT_DIR [--seconds S] [--title T] [--second-device SCRIPT]
# DEVICE_SCRIPT is a scripted device's YAML (scenes/*_push.yaml, *_pull.yaml;
# scenes/idle_device.yaml for the nominal motion alone); it plays as client 1.
# --second-device plays another script at the same time as client 2: two hands
# on one robot (the summary reports each). OUT_DIR gets:
# session.lcmlog, edited_trajectory.yaml, client.log, export/ (CSV and the
# scene), the plots (joints, forces, path, snapshots; PNG and SVG) of the
# scene's end-effector against its obstacles, summary.json and summary.md.
# Port: IGMS_SESSION_PORT (default 7797).
set -euo pipefail
cd "$(dirname "$0")/../.."
usage="usage: scripts/sessions/run_session.sh SCENE DEVICE_SCRIPT OUT_DIR [--seconds S] [--title T] [--second-device SCRIPT]"
scene=${1:?$usage}
device=${2:?$usage}
out=${3:?$usage}
shift 3
seconds="" title="" second=""
while (($#)); do
  case $1 in
    --seconds) seconds=$2; shift 2 ;;
    --title) title=$2; shift 2 ;;
    --second-device) second=$2; shift 2 ;;
    *) echo "run_session.sh: unknown option $1 ($usage)" >&2; exit 2 ;;
  esac
done
[[ -f $scene ]] || { echo "run_session.sh: no scene file $scene" >&2; exit 2; }
[[ -f $device ]] || { echo "run_session.sh: no device script $device" >&2; exit 2; }
[[ -z $second || -f $second ]] || { echo "run_session.sh: no device script $second" >&2; exit 2; }
source scripts/lib/session.sh
igms_in_netns "$0" "$scene" "$device" "$out" ${seconds:+--seconds "$seconds"} ${title:+--title "$title"} \
  ${second:+--second-device "$second"}
# The device script's end: the session's length unless given.
if [[ -z $seconds ]]; then
  seconds=$(/usr/bin/python3 -c 'import sys, yaml; print(float((yaml.safe_load(open(sys.argv[1])) or {}).get("end", 5.0)))' "$device")
fi
mkdir -p "$out"
out=$(cd "$out" && pwd)
url="udpm://239.255.76.67:${IGMS_SESSION_PORT:-7797}?ttl=0"
igms_start_logger "$out/session.lcmlog" "$url" -q --wait-session-s 5 \
  -c 'IGMS_(SESSION_INFO|SESSION_FILES|HAPTIC_INPUT|ROBOT_STATE|SERVER_STATUS|CLIENT_STATUS|CONTACTS)'
igms_start_server "$scene" "$url" --clock lockstep --quiet --save-edited "$out/edited_trajectory.yaml"
if [[ -n $second ]]; then  # the second hand, client 2, alongside
  igms_start_client "$scene" "scripted:$second" "$url" --client-id 2 --duration "$seconds" --connect-timeout 30 \
    2> "$out/client2.log"
fi
igms_run_client "$scene" "scripted:$device" "$url" --client-id 1 --duration "$seconds" --connect-timeout 30 \
  2> "$out/client.log"
igms_wait_clients
igms_stop_all
build/tools/igms-replay export "$out/session.lcmlog" "$out/export" 2>/dev/null
title=${title:-$(basename "$scene" .yaml) + $(basename "$device" .yaml)}
/usr/bin/python3 scripts/reports/plot_session.py "$out/export" --out "$out" --title "$title" >/dev/null
/usr/bin/python3 scripts/reports/session_summary.py "$out" "$title"
