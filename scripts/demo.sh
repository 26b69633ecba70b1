#!/usr/bin/env bash
# The main job: the paper's experiment over the real bus, on a fresh machine.
#   bash scripts/demo.sh            the push experiment (two pushes on link 2, Fig. 6 and 7)
#   bash scripts/demo.sh --pull     the pull experiment (dragging the end-effector, Fig. 8)
#   --out DIR                       write there instead of out/demo
#   --no-setup                      skip the set-up (the packages and the build are there: demo_test)
# Installs and builds (scripts/setup/setup.sh), then, inside a private network
# namespace, starts igms-logger, igms-server (scenes/puma_obstacle.yaml, lockstep)
# and igms-haptic (the scripted device at 1 kHz), stops them cleanly, and writes
# out/demo/: session.lcmlog, edited_trajectory.yaml, the plots (joints, forces,
# path, snapshots; PNG and SVG), summary.md and summary.json, and view_push1.png,
# view_push2.png (or view_pull1.png): the live view at each push, from headless Chromium. For contrast it
# also runs the nominal motion without interaction (out/demo/nominal/), which hits
# the obstacle, and two hands at once (out/demo/two_hands/): a 6-D pull of the
# end-effector (client 1) while a push on link 2 (client 2) acts; its summary
# reports each hand. Then the environment (out/demo/table/, out/demo/go1/):
# the same line across a table with boxes (scenes/table_clear.yaml), first
# without a hand (the arm sweeps a box off its place: table/nominal/), then
# with a scripted hand that pushes the box out of the way before the arm
# arrives (the robot touches no box); and the Go1 standing under gravity while
# a hand pushes its trunk. Each with its plots, summary and live-view screenshots.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=push
out=out/demo
setup=1
while (($#)); do
  case $1 in
    --pull) mode=pull ;;
    --out) out=${2:?--out needs a folder}; shift ;;
    --no-setup) setup=0 ;;
    *) echo "demo: unknown argument $1 (expected --pull, --out DIR, --no-setup)" >&2; exit 2 ;;
  esac
  shift
done
if ((setup)); then
  echo "demo: [1/5] set-up: packages, robot models, Python environments, the build (minutes on a fresh machine)"
  scripts/setup/setup.sh >/dev/null
else
  echo "demo: [1/5] set-up skipped (--no-setup)"
fi
rm -rf "$out"
mkdir -p "$out"
echo "demo: [2/5] the nominal motion, no hand (7 s simulated)"
scripts/sessions/paper_run.sh nominal "$out/nominal" > /dev/null
echo "== without interaction ($out/nominal/summary.md):"
sed -n 4,5p "$out/nominal/summary.md"
echo
echo "demo: [3/5] the paper's $mode experiment over the bus (server, haptic client, logger), then its plots and live-view screenshots"
scripts/sessions/paper_run.sh "$mode" "$out"
echo
# The live view at the moment of each push (or pull), from the recorded session, in headless Chromium.
scripts/reports/screenshot_pushes.py "$out/session.lcmlog" "$out"
echo
echo "demo: [4/5] two hands at once"
echo "== two hands at once ($out/two_hands/summary.md):"
scripts/sessions/paper_run.sh two_hands "$out/two_hands" | sed -n '3,$p'
echo
echo "demo: [5/5] the environment: the line across a table with boxes, then the Go1 pushed on its trunk"
scripts/sessions/run_session.sh scenes/table_clear.yaml scenes/idle_device.yaml "$out/table/nominal" --seconds 6 \
  --title "the line across the table, no hand" > /dev/null
echo "== without a hand ($out/table/nominal/summary.md):"
grep -E "box_b|touched a free body" "$out/table/nominal/summary.md"
echo
echo "== a hand clears the arm's way ($out/table/summary.md):"
scripts/sessions/run_session.sh scenes/table_clear.yaml scenes/table_clear_push.yaml "$out/table" --seconds 6 \
  --title "a hand clears the arm's way" | sed -n '3,$p'
scripts/reports/screenshot_pushes.py "$out/table/session.lcmlog" "$out/table"
echo
echo "== the Go1 standing, a hand pushes its trunk ($out/go1/summary.md):"
scripts/sessions/run_session.sh scenes/go1_stand.yaml scenes/go1_trunk_push.yaml "$out/go1" --seconds 5 \
  --title "the Go1 standing, a hand pushes its trunk" | sed -n '3,$p'
scripts/reports/screenshot_pushes.py "$out/go1/session.lcmlog" "$out/go1"
echo
echo "demo: wrote $out/ (summary.md, plots, view_*.png, session.lcmlog, edited_trajectory.yaml; two_hands/, table/, go1/)"
