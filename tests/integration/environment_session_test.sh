#!/usr/bin/env bash
# An environment over the real bus: the paper's push (scenes/push_demo.yaml) on
# scenes/puma_table.yaml (the PUMA's line past a table with free boxes, which its
# motion knocks over) for 60 s with igms-server in lockstep, igms-haptic and
# igms-logger. The log re-simulates bit for bit (contacts, free bodies and all),
# the export writes environment.csv (every body's pose, the contacts), and the
# summary reports the boxes and the contacts.
#   environment_session_test.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
IGMS_SESSION_PORT=7808 scripts/run_session.sh scenes/puma_table.yaml scenes/push_demo.yaml "$out" --seconds 60
build/tools/igms-replay resim "$out/session.lcmlog" | tee "$out/resim.txt"
grep -q "identical to the recording, bit for bit" "$out/resim.txt" || { echo "environment_session_test: not bit for bit"; exit 1; }
[[ -s $out/export/environment.csv ]] || { echo "environment_session_test: no environment.csv"; exit 1; }
/usr/bin/python3 - "$out" <<'PY'
import csv, json, sys
out = sys.argv[1]
s = json.load(open(out + "/summary.json"))
env = list(csv.DictReader(open(out + "/export/environment.csv")))
checks = [
    (float(env[-1]["t"]) >= 59.9, "60 s of steps"),
    (set(s["bodies"]) == {"box_a", "box_b", "box_c"}, "the three boxes"),
    (max(abs(s["bodies"][b]["end"][1] - s["bodies"][b]["start"][1]) for b in s["bodies"]) > 0.05,
     "the arm knocked a box along its line"),
    (s["max_contacts"] >= 12, "the boxes stand on the table (four corners each)"),
    (s["max_penetration_m"] < 1e-3, "no overlap beyond 1 mm"),
    ("push" in [e["mode"] for e in s["interactions"]], "the hand pushed the arm"),
]
bad = [what for ok, what in checks if not ok]
print("environment_session_test:", "ok" if not bad else "failed: " + "; ".join(bad))
sys.exit(1 if bad else 0)
PY
