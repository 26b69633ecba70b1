#!/usr/bin/env bash
# The accuracy report in one command (about 13 minutes on 2 cores; --quick: shorter):
#  1. every case (the free motions, and a hand's pull and push on the PUMA over
#     k from 0.4 to 32 N/mm) written for the independent engines;
#  2. scripts/reports/accuracy_peers.py in .venv-peers (scripts/setup/peer_env.sh: PyPI pin,
#     mujoco, scipy): the independent truth (SciPy DOP853 on Pinocchio's ABA)
#     and MuJoCo's Euler, implicit, implicitfast and RK4 on the same cases;
#  3. igms's integrators and ODE on every case and step against that truth,
#     h from 1/64 ms to 32 ms (timings: median of 3 runs), and ensembles of 16
#     perturbed starts at 1 ms;
#  4. the committed sessions replayed on ODE; the stability table; the stiff
#     and extreme cases; then the Markdown report and the work-precision plots
#     in out/accuracy/;
#  5. the contact section: igms and ODE (igms-accuracy --contact) and MuJoCo
#     (scripts/bench/contact_peers.py --accuracy) on the contact cases with analytic
#     answers -> out/accuracy/contact.md, contact_work_precision.png.
#   scripts/reports/accuracy.sh [--quick]
set -euo pipefail
cd "$(dirname "$0")/../.."
scripts/setup/setup.sh >/dev/null
scripts/setup/peer_env.sh >/dev/null
out=out/accuracy
rm -rf $out/cases
mkdir -p $out/cases
quick=${1:-}
starts=16
[[ $quick == --quick ]] && starts=4
build/tools/igms-accuracy $quick --write-cases $out/cases
.venv-peers/bin/python scripts/reports/accuracy_peers.py $out/cases $quick | tee $out/peers.txt
build/tools/igms-accuracy $quick --csv $out/accuracy.csv --reference $out/cases --truth-csv $out/truths.csv \
  --ensemble $starts --ensemble-csv $out/ensemble.csv | tee $out/accuracy.txt
build/tools/igms-accuracy --stiffness --csv $out/stability.csv > $out/stability.txt
: > $out/ode_replays.jsonl
for log in paper_nominal.lcmlog.gz paper_push.lcmlog.gz paper_pull.lcmlog.gz push.lcmlog; do
  for mode in "" --track; do
    build/tools/igms-ode-ref log tests/replay/data/$log $mode --json >> $out/ode_replays.jsonl
  done
done
status=0
build/tools/igms-accuracy --extreme $quick --csv $out/extreme.csv | tee $out/extreme.txt || status=$?
/usr/bin/python3 scripts/reports/accuracy_report.py $out/accuracy.csv $out --peers $out/cases/mujoco.csv \
  --truths $out/truths.csv --ensemble $out/ensemble.csv --stability $out/stability.csv \
  --replays $out/ode_replays.jsonl --extreme $out/extreme.csv > /dev/null
mkdir -p $out/contact_cases
build/tools/igms-accuracy --contact $quick --csv $out/contact.csv | tee $out/contact.txt || status=$?
build/tools/igms-accuracy --contact --write-cases $out/contact_cases > /dev/null
.venv-peers/bin/python scripts/bench/contact_peers.py --accuracy $out/contact_cases --csv $out/contact_mujoco.csv $quick
/usr/bin/python3 scripts/reports/contact_accuracy_report.py $out/contact.csv $out/contact_mujoco.csv $out
echo "accuracy: wrote $out/ (accuracy.md, work_precision.png/svg, contact.md, contact_work_precision.png, the CSVs, cases/ with the truths)"
exit $status
