#!/usr/bin/env bash
# The README's "Your own robot in ten minutes", run as written: every ```bash
# block of that section in order, from the repository's root, with its folders
# (my_robot/, out/z1_*) renamed to this run's own so that nothing of a user's
# is touched; then the summaries must show the push, the pull and the target
# reached. Exit 77 (skipped) without example-robot-data.
#   walkthrough_test.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
[[ -d third_party/example-robot-data/robots/z1_description ]] || { echo "skipped: example-robot-data not fetched"; exit 77; }
mine="walkthrough_test_$$"
trap 'rm -rf "$mine" "out/$mine"' EXIT
script=$(/usr/bin/python3 - "$mine" <<'PY'
import re, sys
mine = sys.argv[1]
text = open("README.md").read()
section = text.split("## Your own robot in ten minutes", 1)[1].split("\n## ", 1)[0]
blocks = re.findall(r"```bash\n(.*?)```", section, re.S)
assert len(blocks) >= 4, "the walkthrough's command blocks"
body = "\n".join(blocks).replace("my_robot", mine).replace("out/z1_", f"out/{mine}/z1_")
print("set -euo pipefail\n" + body)
PY
)
mkdir -p "out/$mine"
IGMS_SESSION_PORT=7807 bash -c "$script"
/usr/bin/python3 - "out/$mine" <<'PY'
import json, sys
out = sys.argv[1]
push, pull = (json.load(open(f"{out}/z1_{k}/summary.json")) for k in ("push", "pull"))
checks = [
    ([e["mode"] for e in push["interactions"]] == ["push"], "one push"),
    (push["max_force_on_robot_N"] > 5.0, "the push presses the forearm"),
    ([e["mode"] for e in pull["interactions"]] == ["pull"], "one pull and no push after it"),
    (pull["max_force_on_robot_N"] > 1.0, "the pull drags the gripper"),
    (push["reached_target"] and pull["reached_target"], "generation resumes to the target"),
    (push["end_effector"] == "gripperStator", "the scene's end-effector"),
]
bad = [what for ok, what in checks if not ok]
print("walkthrough_test:", "ok" if not bad else "failed: " + "; ".join(bad))
sys.exit(1 if bad else 0)
PY
