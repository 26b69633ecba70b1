#!/usr/bin/env bash
# The Panda from example-robot-data over the real bus (private network
# namespace): igms-logger, igms-server (lockstep) on scenes/panda_obstacle.yaml
# and igms-haptic with the scripted push on link 4's collision mesh; the
# recorded states show the push (mode 1, a force on the robot). Exit 77
# (skipped) when the models were not fetched.
#   real_robot_bus_test.sh BUILD_DIR
set -euo pipefail
cd "$(dirname "$0")/../.."
export IGMS_BUILD=$1
[[ -d third_party/example-robot-data/robots/panda_description ]] || { echo "skipped: example-robot-data not fetched"; exit 77; }
source scripts/lib/session.sh
igms_in_netns "$0" "$@"
out=$(mktemp -d)
trap 'igms_stop_all; rm -rf "$out"' EXIT
url="udpm://239.255.76.67:7725?ttl=0"
igms_start_logger "$out/panda.lcmlog" "$url" -q --wait-session-s 5 -c 'IGMS_(SESSION_INFO|HAPTIC_INPUT|ROBOT_STATE)'
igms_start_server scenes/panda_obstacle.yaml "$url" --clock lockstep --quiet
sleep 2  # the Panda's meshes become distance fields at load (about 2 s)
igms_run_client scenes/panda_obstacle.yaml scripted:scenes/panda_push.yaml "$url" --duration 2 --connect-timeout 20 2> "$out/client.log"
igms_stop_all
"$IGMS_BUILD/tools/igms-replay" export "$out/panda.lcmlog" "$out/export" 2>/dev/null
python3 - "$out/export/states.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
push = [r for r in rows if r["mode"] == "1"]
force = max((sum(float(r[k]) ** 2 for k in ("fx", "fy", "fz")) ** 0.5 for r in push), default=0.0)
print("panda over the bus: %d states, %d in push mode, largest force on the robot %.2f N" % (len(rows), len(push), force))
sys.exit(0 if len(rows) > 1500 and len(push) > 100 and force > 1.0 else 1)
PY
