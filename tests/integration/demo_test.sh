#!/usr/bin/env bash
# The README's first command, as a person runs it: `bash scripts/demo.sh`
# (with --out, so that a user's out/demo is not touched, and --no-setup: the
# set-up is scripts/test.sh's own, and a configure in the middle of a test run
# would rewrite the build other tests are using). It shows its stages from its
# first line, ends with both runs' summaries, and writes what it announces: the
# paper's push (collision-free, the wall reached) with its plots and live-view
# screenshots, the two hands, and the environment (a hand clears the arm's
# way: the robot touches no box, the box ends on the table; the Go1 pushed on
# its trunk).
#   demo_test.sh BUILD_DIR
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "$1" && pwd)
[[ $build == "$src/build" ]] || { echo "skipped: scripts/demo.sh runs build/ ($build is another build)"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$src"
fail() { echo "demo_test: $*" >&2; exit 1; }
bash scripts/demo.sh --out "$work/demo" --no-setup > "$work/demo.txt" 2>&1 || { tail -40 "$work/demo.txt"; fail "scripts/demo.sh failed"; }
cat "$work/demo.txt"
cd "$work"
[[ $(head -1 demo.txt) == "demo: [1/5] set-up"* ]] || fail "the first line is not the first stage"
for stage in 2 3 4 5; do grep -q "^demo: \[$stage/5\]" demo.txt || fail "stage $stage/5 not shown"; done
grep -q "^demo: wrote $work/demo/" demo.txt || fail "no closing line"
for f in summary.md session.lcmlog path.png view_push1.png view_push2.png two_hands/summary.md \
         table/nominal/summary.md table/summary.md table/view_push1.png go1/summary.md go1/view_push1.png; do
  [[ -s demo/$f ]] || fail "demo/$f was not written"
done
/usr/bin/python3 - <<'PY'
import json
push, table, go1 = (json.load(open("demo/%s/summary.json" % d)) for d in (".", "table", "go1"))
box = table["bodies"]["box_b"]
checks = [
    (push["collision_free"] and push["reached_target"], "the paper's push: collision-free, the wall reached"),
    ([i["mode"] for i in push["interactions"]] == ["push", "push"], "the paper's push: two pushes"),
    (table["collision_free"] and not table["robot_touched_bodies"], "the table: the hand cleared the way, no box touched"),
    (abs(box["end"][2] - 0.16) < 1e-3 and box["end"][0] - box["start"][0] > 0.05, "the table: box_b pushed, on the table"),
    (go1["interactions"] and go1["interactions"][0]["mode"] == "push", "the Go1: a hand pushed its trunk"),
]
for ok, what in checks:
    print("  %s %s" % ("ok  " if ok else "FAIL", what))
raise SystemExit(0 if all(ok for ok, _ in checks) else 1)
PY
echo "demo_test: ok"
