#!/usr/bin/env bash
# The accuracy report in one command (a few minutes): every case, every method,
# h from 1/64 ms to 32 ms (timings: median of 3 runs); the committed sessions
# replayed on ODE (igms-ode-ref, open loop and tracking); the stiff and extreme
# cases; then the Markdown report and the work-precision plot in out/accuracy/.
#   scripts/accuracy.sh [--quick]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null
out=out/accuracy
mkdir -p $out
quick=${1:-}
build/tools/igms-accuracy $quick --csv $out/accuracy.csv | tee $out/accuracy.txt
: > $out/ode_replays.jsonl
for log in paper_nominal.lcmlog.gz paper_push.lcmlog.gz paper_pull.lcmlog.gz push.lcmlog; do
  for mode in "" --track; do
    build/tools/igms-ode-ref log tests/replay/data/$log $mode --json >> $out/ode_replays.jsonl
  done
done
status=0
build/tools/igms-accuracy --extreme $quick --csv $out/extreme.csv | tee $out/extreme.txt || status=$?
/usr/bin/python3 scripts/accuracy_report.py $out/accuracy.csv $out --replays $out/ode_replays.jsonl \
  --extreme $out/extreme.csv > /dev/null
echo "accuracy: wrote $out/ (accuracy.md, work_precision.png/svg, accuracy.csv, extreme.csv, ode_replays.jsonl)"
exit $status
