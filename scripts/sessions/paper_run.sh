#!/usr/bin/env bash
# One of the paper's experiments over the real bus (Son et al. 2003, section V):
# scripts/sessions/run_session.sh on scenes/puma_obstacle.yaml with the paper's push or
# pull script, the device held away (nominal), or two hands at once (two_hands: the pull of
# scenes/paper_two_hands_pull.yaml as client 1 with the push of scenes/paper_two_hands_push.yaml
# as client 2), for 7 s.
#   scripts/sessions/paper_run.sh push|pull|nominal|two_hands OUT_DIR
# OUT_DIR gets: session.lcmlog, edited_trajectory.yaml, export/ (CSV), the
# plots (joints, forces, path, snapshots; PNG and SVG), summary.json and summary.md.
set -euo pipefail
cd "$(dirname "$0")/../.."
mode=${1:?push, pull, nominal or two_hands}
out=${2:?output directory}
extra=()
case $mode in
  push) device=scenes/paper_push.yaml ;;
  pull) device=scenes/paper_pull.yaml ;;
  nominal) device=scenes/idle_device.yaml ;;
  two_hands) device=scenes/paper_two_hands_pull.yaml; extra=(--second-device scenes/paper_two_hands_push.yaml) ;;
  *) echo "paper_run.sh: push, pull, nominal or two_hands" >&2; exit 2 ;;
esac
IGMS_SESSION_PORT=${IGMS_PAPER_PORT:-7797} exec scripts/sessions/run_session.sh scenes/puma_obstacle.yaml $device "$out" \
  --seconds 7 --title "$mode" "${extra[@]}"
