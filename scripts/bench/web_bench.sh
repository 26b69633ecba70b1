#!/usr/bin/env bash
# The browser view's benchmark (scripts/bench/web_view_bench.py): fps in headless
# Chromium (PUMA, 40-dof humanoid), the server's step p99 with and without
# the view, bandwidth, mouse-to-draw latency. In a private network namespace.
#   bash scripts/bench/web_bench.sh        (IGMS_WEB_BENCH_SECONDS=N: window length, default 10)
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/lib/session.sh
igms_in_netns "$0" "$@"
[[ -n "${IGMS_WEB_BENCH_NO_SETUP:-}" ]] || scripts/setup/setup.sh >/dev/null
mkdir -p out/bench
/usr/bin/python3 scripts/bench/web_view_bench.py "${IGMS_BUILD:-build}" | tee out/bench/web_view.txt
