#!/usr/bin/env bash
# Set up, build and run the test suites (ctest). Extra arguments go to ctest,
# e.g. scripts/test.sh -L crosscheck. The long `stress` label is left out by
# default (run it with scripts/test.sh -L stress).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cd build
if [[ $# -eq 0 ]]; then set -- -LE stress; fi
ctest --output-on-failure -j "$(nproc)" "$@"
