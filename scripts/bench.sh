#!/usr/bin/env bash
# Benchmarks: igms vs KDL in one run (medians and ratios), then igms-dyn bench
# per model. Results also go to out/bench/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null
mkdir -p out/bench
build/bench/igms-bench --json out/bench/igms_vs_kdl.json "$@" | tee out/bench/igms_vs_kdl.txt
for m in puma560.urdf arm7.urdf; do build/tools/igms-dyn bench --model models/$m; done | tee out/bench/igms_dyn.txt
build/tools/igms-dyn bench --model models/quadruped.urdf --floating-base | tee -a out/bench/igms_dyn.txt
