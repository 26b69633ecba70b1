#!/usr/bin/env bash
# A sweep scales out with nothing changed but --address: a Ray cluster of two hosts, each a network
# namespace with one CPU, joined by a veth pair (the namespaces and the link exist only for this test):
# the head on 10.78.0.1, a worker node on 10.78.0.2. igms-sweep on the head with --address runs the
# spec; every run succeeds, the rows equal a serial loop's, and runs ran on both hosts (the rows' worker column).
#   ray_cluster_test.sh SOURCE_DIR
set -euo pipefail
source=$(cd "$1" && pwd)
venv=$source/.venv/bin
a=igmsray-a-$$ b=igmsray-b-$$
out=$(mktemp -d)
cleanup() {
  ip netns exec "$b" "$venv/ray" stop --force >/dev/null 2>&1 || true
  ip netns exec "$a" "$venv/ray" stop --force >/dev/null 2>&1 || true
  ip netns pids "$a" 2>/dev/null | xargs -r kill -9 2>/dev/null || true
  ip netns pids "$b" 2>/dev/null | xargs -r kill -9 2>/dev/null || true
  ip netns del "$a" 2>/dev/null || true
  ip netns del "$b" 2>/dev/null || true
  rm -rf "$out"
}
trap cleanup EXIT
source "$source/scripts/lib/veth_pair.sh"
igms_veth_pair "$a" "$b" "ra$$" "rb$$" 10.78.0
export RAY_USAGE_STATS_ENABLED=0 RAY_AUTH_MODE=token  # every node and the driver: the cluster's token (~/.ray/auth_token)
ip netns exec "$a" "$venv/ray" start --head --node-ip-address 10.78.0.1 --port 6390 --num-cpus 1 \
  --include-dashboard false --disable-usage-stats >"$out/head.log" 2>&1 || { cat "$out/head.log"; exit 1; }
ip netns exec "$b" "$venv/ray" start --address 10.78.0.1:6390 --node-ip-address 10.78.0.2 --num-cpus 1 \
  --disable-usage-stats >"$out/worker.log" 2>&1 || { cat "$out/worker.log"; exit 1; }
cd "$source"
ip netns exec "$a" "$venv/igms-sweep" examples/sweeps/box_slide.yaml --out "$out/cluster" --address 10.78.0.1:6390 \
  --no-progress
"$venv/igms-sweep" examples/sweeps/box_slide.yaml --out "$out/serial" --serial --no-progress
"$venv/python" - "$out" <<'PY'
import sys
import numpy as np
import pandas as pd
out = sys.argv[1]
cluster, serial = pd.read_parquet(out + "/cluster/results.parquet"), pd.read_parquet(out + "/serial/results.parquet")
assert len(cluster) == 1000 and cluster["error"].isna().all(), cluster["error"].dropna().head()
for column in serial.columns:
    if column not in ("duration_s", "worker", "error"):
        a, b = cluster[column], serial[column]
        assert np.array_equal(np.stack(a) if a.dtype == object else a, np.stack(b) if b.dtype == object else b), column
hosts = cluster["worker"].str.split(":").str[0]
on_a, on_b = (hosts == "10.78.0.1").sum(), (hosts == "10.78.0.2").sum()
print(f"ray_cluster_test: 1000 runs, bit-identical to the serial loop; {on_a} ran on the head, {on_b} on the other host")
assert on_a > 0 and on_b > 0 and on_a + on_b == 1000
PY
echo "ray_cluster_test: passed"
