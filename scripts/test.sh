#!/usr/bin/env bash
# Set up, build and run every test suite (ctest, all labels: unit, crosscheck,
# replay, integration, stress; about 5 minutes on 2 cores). Extra arguments go
# to ctest, e.g. scripts/test.sh -L crosscheck, or -LE stress to skip the
# minute of stress tests.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup/setup.sh
cd build
ctest --output-on-failure -j "$(nproc)" "$@"
