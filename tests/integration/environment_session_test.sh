#!/usr/bin/env bash
# An environment over the real bus: the paper's push (scenes/push_demo.yaml) on
# scenes/puma_table.yaml (the PUMA's line past a table with free boxes, which its
# motion knocks over) for 60 s with igms-server in lockstep, igms-haptic and
# igms-logger. The log re-simulates bit for bit (contacts, free bodies and all),
# the export writes environment.csv (every body's pose, the contacts), and the
# summary reports the boxes and the contacts. The contacts channel
# (IGMS_CONTACTS) is in the log, read by igmslog: every 10th step at the
# default 100 Hz, and the table carries the three boxes' weight.
#   environment_session_test.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
IGMS_SESSION_PORT=7808 scripts/sessions/run_session.sh scenes/puma_table.yaml scenes/push_demo.yaml "$out" --seconds 60
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
python=$(scripts/setup/python_env.sh)
PYTHONPATH="python:build/python" "$python" - "$out/session.lcmlog" <<'PY'
import sys
import numpy as np
import igmslog
log = igmslog.read(sys.argv[1])
names = igmslog.link_names(log)
m, c = log.contact_messages, log.contacts
boxes = [names.index(b) for b in ("box_a", "box_b", "box_c")]
# The first message after 0.2 s, before the arm reaches a box: the boxes rest on the table.
seq = next(s for s, t in zip(m["seq"], m["sim_time"]) if t > 0.2)
rows = c["seq"] == seq
on_boxes = sum((f if b in boxes else -f if a in boxes else 0 * f)
               for a, b, f in zip(c["link_a"][rows], c["link_b"][rows], c["force"][rows]))
weight = 3 * 0.3 * 9.81
checks = [
    (len(m["seq"]) >= 5900, "about 100 contact messages a second for 60 s (%d)" % len(m["seq"])),
    (np.all(m["seq"] % 10 == 0), "on every 10th step"),
    (np.all(m["ncontacts"] == np.minimum(m["total"], 512)), "every contact sent"),
    (abs(on_boxes[2] - weight) < 0.01 * weight, "the table carries the boxes: %.4f N of %.4f N" % (on_boxes[2], weight)),
    (np.all(np.abs(np.linalg.norm(c["normal"], axis=1) - 1) < 1e-9), "unit normals"),
    (log.undecodable["IGMS_CONTACTS"] == 0, "every contacts message decodes"),
]
bad = [what for ok, what in checks if not ok]
for ok, what in checks:
    print("  %s %s" % ("ok  " if ok else "FAIL", what))
print("environment_session_test contacts:", "ok" if not bad else "failed")
sys.exit(1 if bad else 0)
PY
