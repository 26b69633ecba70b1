#!/usr/bin/env bash
# scripts/sessions/run_session.sh on a robot that is not the PUMA (the Panda from
# example-robot-data, pushed on link 4): the session runs, the plots are
# written, and the summary follows the scene's own end-effector and target
# (it used to need the PUMA's ee_link). Exit 77 (skipped) without the models.
#   run_session_test.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
[[ -d third_party/example-robot-data/robots/panda_description ]] || { echo "skipped: example-robot-data not fetched"; exit 77; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
IGMS_SESSION_PORT=7806 scripts/sessions/run_session.sh scenes/panda_obstacle.yaml scenes/panda_push.yaml "$out" --seconds 4
for f in summary.md summary.json joints.png forces.png path.png snapshots.png edited_trajectory.yaml; do
  [[ -s $out/$f ]] || { echo "run_session_test: $f missing"; exit 1; }
done
/usr/bin/python3 - "$out/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
checks = [
    (s["end_effector"] == "panda_hand_tcp", "the scene's end-effector (its trajectory frame)"),
    (s["reached_target"] is True, "the hand reached the line's target"),
    ([e["mode"] for e in s["interactions"]] == ["push"], "one push"),
    (s["touches_without_force"] <= 2, "at most two stray touches of the estimate without force"),
    (s["max_force_on_robot_N"] > 1.0, "a force on the robot"),
    (abs(s["client_rate_hz"] - 1000) < 50, "the client's rate from its logged status"),
    ("reached_wall" not in s, "no wall in this scene"),
]
bad = [what for ok, what in checks if not ok]
print("run_session_test:", "ok" if not bad else "failed: " + "; ".join(bad))
sys.exit(1 if bad else 0)
PY
