#!/usr/bin/env bash
# The paper's push (realtime server, scripted client) with nothing else running,
# with one spinning process (the other core busy) and with three (both cores
# and more), each as shipped and with --rt-priority 20 for the server and the
# client; inside a private network namespace. Prints the client's rate, late
# cycles, skipped periods, deadline misses and largest force step per case.
#   scripts/bench/load_bench.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-7}
source scripts/lib/session.sh
igms_in_netns "$0" "$@"
url="udpm://239.255.76.67:7870?ttl=0"
printf '| load | scheduling | client rate | late cycles | skipped periods | deadline misses | largest force step | server overruns |\n'
printf '|---|---|---:|---:|---:|---:|---:|---:|\n'
for spinners in 0 1 3; do
  for rt in 0 20; do
    pids=()
    for ((i = 0; i < spinners; i++)); do (while :; do :; done) & pids+=($!); done
    "$igms_build/server/igms-server" --scene scenes/puma_obstacle.yaml --lcm-url "$url" --rt-priority $rt \
      > /tmp/igms_load_server.$$ 2>&1 &
    server=$!
    sleep 0.3
    out=$("$igms_build/haptic_client/igms-haptic" --scene scenes/puma_obstacle.yaml \
      --device scripted:scenes/paper_push.yaml --lcm-url "$url" --duration "$seconds" --rt-priority $rt 2>&1 || true)
    kill -INT $server; wait $server 2>/dev/null || true
    overruns=$(grep -o 'overruns=[0-9]*' /tmp/igms_load_server.$$ | tail -1 | cut -d= -f2)
    rm -f /tmp/igms_load_server.$$
    for p in "${pids[@]}"; do kill "$p"; done
    wait "${pids[@]}" 2>/dev/null || true
    rate=$(sed -n 's/.*cycles in [0-9.]* s (\([0-9.]*\) Hz), \([0-9]*\) deadline misses.*max force step \([0-9.]*\) N.*/\1 Hz|\2|\3 N/p' <<< "$out")
    late=$(sed -n 's/.*: \([0-9]*\) cycles started over a period late (caught up), \([0-9]*\) periods skipped.*/\1|\2/p' <<< "$out")
    IFS='|' read -r r misses step <<< "$rate"
    IFS='|' read -r l skipped <<< "$late"
    sched=$([[ $rt == 0 ]] && echo "as shipped" || echo "SCHED_FIFO 20")
    printf '| %s spinning | %s | %s | %s | %s | %s | %s | %s |\n' "$spinners" "$sched" "$r" "$l" "$skipped" "$misses" \
      "$step" "${overruns:-?}"
  done
done
