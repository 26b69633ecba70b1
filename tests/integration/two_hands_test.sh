#!/usr/bin/env bash
# Two hands on one robot over the real bus (private network namespace):
#  1. lockstep: client 1 pulls the end-effector in 6-D (scenes/paper_two_hands_pull.yaml)
#     while client 2 pushes link 2 (scenes/paper_two_hands_push.yaml); the log shows both
#     couplings acting in the same steps, each hand's own force, and it re-simulates bit for
#     bit in process (igms-replay resim: the in-process run of the summed couplings);
#  2. realtime: the same two clients, client 2 stopped (SIGSTOP) for 0.5 s during its push:
#     its coupling is released after its hold, the server status lists it as released while
#     client 1 stays active, and client 1's rate and force run on undisturbed.
#   tests/integration/two_hands_test.sh BUILD_DIR PORT
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "$1" && pwd)
port=$2
cd "$src"
export IGMS_BUILD=$build
source scripts/lib/session.sh
igms_in_netns "$src/tests/integration/two_hands_test.sh" "$@"
python=$("$src/scripts/setup/python_env.sh")
tmp=$(mktemp -d)
trap 'igms_stop_all; rm -rf "$tmp"' EXIT
url="udpm://239.255.76.67:$port?ttl=0"
scene=scenes/puma_obstacle.yaml
channels='IGMS_(SESSION_INFO|HAPTIC_INPUT|ROBOT_STATE|SERVER_STATUS|CLIENT_STATUS)'

echo "== 1. lockstep, two hands at once"
igms_start_logger "$tmp/lockstep.lcmlog" "$url" -c "$channels" -q --wait-session-s 5
igms_start_server $scene "$url" --clock lockstep --quiet
igms_start_client $scene scripted:scenes/paper_two_hands_push.yaml "$url" --quiet --client-id 2 --duration 2
igms_run_client $scene scripted:scenes/paper_two_hands_pull.yaml "$url" --quiet --client-id 1 --duration 2
igms_wait_clients
igms_stop_all
"$build/tools/igms-replay" resim "$tmp/lockstep.lcmlog" --require-identical --base-dir "$src" | tail -1
PYTHONPATH="$src/python:$build/python" "$python" tests/integration/two_hands_check.py lockstep "$tmp/lockstep.lcmlog"

echo "== 2. realtime, client 2 stopped for 0.5 s"
igms_start_logger "$tmp/stall.lcmlog" "$url" -c "$channels" -q --wait-session-s 5
igms_start_server $scene "$url" --quiet
igms_start_client $scene scripted:scenes/paper_two_hands_push.yaml "$url" --quiet --client-id 2 --duration 2.5
stalled=${igms_client_pids[0]}
igms_start_client $scene scripted:scenes/paper_two_hands_pull.yaml "$url" --quiet --client-id 1 --duration 2.5
sleep 0.8
kill -STOP "$stalled"
sleep 0.5
kill -CONT "$stalled"
igms_wait_clients
igms_stop_all
PYTHONPATH="$src/python:$build/python" "$python" tests/integration/two_hands_check.py stall "$tmp/stall.lcmlog"
echo "two_hands_test: passed"
