#!/usr/bin/env bash
# Set up, build and run the test suites (ctest). Extra arguments go to ctest,
# e.g. scripts/test.sh -L crosscheck.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cd build
ctest --output-on-failure -j "$(nproc)" "$@"
