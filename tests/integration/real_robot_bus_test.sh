#!/usr/bin/env bash
# Robots from example-robot-data over the real bus (private network
# namespace), one session each: igms-logger, igms-server (lockstep) and
# igms-haptic with a scripted device. The Panda pushed on link 4's collision
# mesh and pulled by its hand, the UR5 pushed on its forearm mesh, the
# floating Solo12 pushed on its torso mesh. The recorded states show each
# interaction (its mode, a force on the robot) and the pushed link, or the
# pulled hand, off the path it takes in the same session with an idle device. Exit 77 (skipped) when
# the models were not fetched.
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

session() {  # NAME SCENE DEVICE_SCRIPT
  local name=$1 scene=$2 device=$3
  igms_start_logger "$out/$name.lcmlog" "$url" -q --wait-session-s 5 -c 'IGMS_(SESSION_INFO|SERVER_STATUS|HAPTIC_INPUT|ROBOT_STATE)'
  igms_start_server "$scene" "$url" --clock lockstep --quiet
  sleep 2  # meshes become distance fields at load (about 2 s without the cache)
  igms_run_client "$scene" "scripted:$device" "$url" --duration 2 --connect-timeout 20 2> "$out/$name.client.log"
  igms_stop_all
  "$IGMS_BUILD/tools/igms-replay" export "$out/$name.lcmlog" "$out/$name" 2>/dev/null
}

check() {  # NAME MODE [IDLE_NAME LINK]: the interaction's states, and how far it moved LINK
  python3 - "$1" "$2" "$out/$1/states.csv" "${3:+$out/$3/states.csv}" "${4:-}" <<'PY'
import csv, sys
name, mode, states, calm, link = sys.argv[1:6]
rows = list(csv.DictReader(open(states)))
act = [r for r in rows if r["mode"] == mode]
force = max((sum(float(r[k]) ** 2 for k in ("fx", "fy", "fz")) ** 0.5 for r in act), default=0.0)
line = "%-14s over the bus: %d states, %d in mode %s, largest force on the robot %.2f N" % (name, len(rows), len(act), mode, force)
ok = len(rows) > 1500 and len(act) > 100 and force > 1.0
if calm:
    # The same simulated time in the run with the idle device: how far the push moved the link.
    quiet = {round(float(r["t"]), 4): r for r in csv.DictReader(open(calm))}
    axes = [link + "." + a for a in "xyz"]
    moved, matched = 0.0, 0
    for r in rows:
        c = quiet.get(round(float(r["t"]), 4))
        if c:
            matched += 1
            moved = max(moved, sum((float(r[k]) - float(c[k])) ** 2 for k in axes) ** 0.5)
    line += ", %s off its idle path by up to %.1f mm (%d times matched)" % (link, 1000 * moved, matched)
    ok = ok and matched > 1000 and moved > 0.01
print(line)
sys.exit(0 if ok else 1)
PY
}

fail=0
session panda_idle scenes/panda_obstacle.yaml scenes/idle_device.yaml
session panda_push scenes/panda_obstacle.yaml scenes/panda_push.yaml
check panda_push 1 panda_idle panda_link4 || fail=1
session panda_pull scenes/panda_obstacle.yaml scenes/panda_pull.yaml
check panda_pull 2 panda_idle panda_hand || fail=1
session ur5_idle scenes/ur5_line.yaml scenes/idle_device.yaml
session ur5_push scenes/ur5_line.yaml scenes/ur5_push.yaml
check ur5_push 1 ur5_idle forearm_link || fail=1
session solo12_idle scenes/solo12_float.yaml scenes/idle_device.yaml
session solo12_push scenes/solo12_float.yaml scenes/solo12_push.yaml
check solo12_push 1 solo12_idle base_link || fail=1
exit $fail
