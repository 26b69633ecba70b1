#!/usr/bin/env bash
# Records the replay suite (tests/replay/data/*.lcmlog) with the real server,
# client and logger, in a private network namespace:
#   push     a scripted push on link 3
#   pull     a scripted pull of the end-effector
#   dropped  the push with 20 % of the server's replies dropped
#   paper_push, paper_pull  the paper's experiments (scenes/puma_obstacle.yaml), gzip-compressed
#   paper_nominal  the same scene with the device held away: the controlled straight line alone
#   paper_two_hands  two clients at once: the 6-D pull of the end-effector (client 1) while the
#                  push on link 2 (client 2) acts (scenes/paper_two_hands_*.yaml)
# First it shows how far the current build's re-simulation of the committed
# logs moved; the new logs replace them only with --accept.
#   scripts/sessions/record_replay_suite.sh [--accept]
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/lib/session.sh
igms_in_netns "$0" "$@"
accept=${1:-}
out=out/replay_suite
mkdir -p "$out"
url="udpm://239.255.76.67:7795?ttl=0"
channels='IGMS_(SESSION_INFO|SESSION_FILES|HAPTIC_INPUT|ROBOT_STATE|ROBOT_STATE_TRUTH)'

record() {  # name script[+second_script] [server options...]
  local name=$1 script=${2%%+*} second=""
  [[ $2 == *+* ]] && second=${2#*+}
  shift 2
  local scene=scenes/puma_wall.yaml seconds=""
  if [[ $name == paper_* ]]; then scene=scenes/puma_obstacle.yaml; seconds="--duration 6"; fi
  local only=$channels
  [[ "$*" == *fault* ]] && only='IGMS_(SESSION_INFO|SESSION_FILES|HAPTIC_INPUT|ROBOT_STATE_TRUTH)'
  igms_start_logger "$out/$name.lcmlog" "$url" -c "$only" -q --wait-session-s 5
  igms_start_server $scene "$url" --clock lockstep --quiet "$@"
  if [[ -n $second ]]; then igms_start_client $scene "scripted:$second" "$url" --quiet --client-id 2 $seconds; fi
  igms_run_client $scene "scripted:$script" "$url" --quiet --client-id 1 $seconds
  igms_wait_clients
  igms_stop_all
  if [[ $name == paper_* ]]; then gzip -f "$out/$name.lcmlog"; fi
  echo "recorded $name"
}

record push tests/replay/push_short.yaml
record pull tests/replay/pull_short.yaml
record dropped tests/replay/push_short.yaml --fault-drop 0.2
record paper_push scenes/paper_push.yaml
record paper_pull scenes/paper_pull.yaml
record paper_nominal scenes/idle_device.yaml
record paper_two_hands scenes/paper_two_hands_pull.yaml+scenes/paper_two_hands_push.yaml

for log in tests/replay/data/*.lcmlog*; do
  echo "== the committed $log, re-simulated by this build:"
  build/tools/igms-replay resim "$log" --tolerance 1e300 || true
done
if [[ "$accept" == "--accept" ]]; then
  cp "$out"/{push,pull,dropped}.lcmlog "$out"/paper_{push,pull,nominal,two_hands}.lcmlog.gz tests/replay/data/
  echo "accepted: tests/replay/data/ now holds the new recordings"
else
  echo "not accepted: rerun with --accept to replace tests/replay/data/"
fi
