#!/usr/bin/env bash
# The full accuracy sweep (a few minutes): every case, every method, h from
# 1/64 ms to 32 ms, then the work-precision report in out/accuracy/.
#   scripts/accuracy.sh [--quick]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null
mkdir -p out/accuracy
build/tools/igms-accuracy ${1:-} --csv out/accuracy/accuracy.csv | tee out/accuracy/accuracy.txt
/usr/bin/python3 scripts/accuracy_report.py out/accuracy/accuracy.csv out/accuracy > /dev/null
echo "accuracy: wrote out/accuracy/ (accuracy.csv, accuracy.md, work_precision.png/svg)"
