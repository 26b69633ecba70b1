#!/usr/bin/env bash
# The paper's push and pull through igms-relay at one-way delays of 0 to 50 ms
# (constant and +-50 % jitter) and 10 % loss, the server on its realtime clock,
# inside a private network namespace; prints the table (scripts/bench/latency_bench.py).
#   scripts/bench/latency_bench.sh [--quick | --box] [--seconds 7] [--out DIR] [-- igms-haptic options]
# --box: a hand pushing a box out of the arm's way on scenes/table_clear.yaml instead.
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/lib/session.sh
igms_in_netns "$0" "$@"
exec /usr/bin/python3 scripts/bench/latency_bench.py "$@"
