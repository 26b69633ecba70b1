#!/usr/bin/env bash
# The paper's set-up on two hosts: igms-server in one network namespace and
# igms-haptic in another, joined by a veth pair (a real network stack:
# multicast routed over the link, ttl=1 only there; the namespaces and the
# link exist only for this test). The scripted push runs over it: the
# server's states reach the client and the client's inputs reach the server,
# and the client holds 1 kHz. The link is where a stranger could sit, so the
# two hosts share a bus key (the same file, as copied to both machines): every
# message crosses signed and is checked, and neither side refuses any.
#   two_hosts_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 source=$2
a=igms2h-a-$$ b=igms2h-b-$$
out=$(mktemp -d)
cleanup() {
  ip netns pids "$a" 2>/dev/null | xargs -r kill 2>/dev/null || true
  ip netns pids "$b" 2>/dev/null | xargs -r kill 2>/dev/null || true
  ip netns del "$a" 2>/dev/null || true
  ip netns del "$b" 2>/dev/null || true
  [[ -n ${KEEP:-} ]] || rm -rf "$out"
}
trap cleanup EXIT
source "$source/scripts/lib/veth_pair.sh"
igms_veth_pair "$a" "$b" "va$$" "vb$$" 10.77.0
url="udpm://239.255.76.67:7723?ttl=1"  # ttl=1: one hop, the private link only
source "$source/scripts/lib/bus_key.sh"
igms_new_key "$out/bus.key"
export IGMS_KEY_FILE=$out/bus.key
ip netns exec "$a" "$build/server/igms-server" --scene "$source/scenes/puma_obstacle.yaml" --lcm-url "$url" \
  --clock lockstep --quiet > "$out/server.log" 2>&1 &
server=$!
sleep 0.5
ip netns exec "$b" "$build/haptic_client/igms-haptic" --scene "$source/scenes/puma_obstacle.yaml" \
  --device "scripted:$source/scenes/paper_push.yaml" --lcm-url "$url" --duration 3 2> "$out/client.log"
kill "$server" 2>/dev/null || true
wait "$server" 2>/dev/null || true
cat "$out/client.log"
line=$(grep "cycles in" "$out/client.log")
rate=$(sed -n 's/.*(\([0-9.]*\) Hz).*/\1/p' <<<"$line")
replies=$(sed -n 's/.*(\([0-9]*\) replies).*/\1/p' "$out/client.log")
echo "two hosts: client rate $rate Hz, $replies replies over the veth link"
awk -v r="$rate" 'BEGIN { exit !(r >= 990) }' || { echo "FAIL: the client did not hold 1 kHz"; exit 1; }
((replies > 2500)) || { echo "FAIL: only $replies of the server's replies crossed the link"; exit 1; }
grep -q "igms-haptic: bus: accepted [0-9]*, refused 0$" "$out/client.log" ||
  { echo "FAIL: the client refused signed messages or checked none"; exit 1; }
grep -q "igms-server: bus: accepted [0-9]*, refused 0$" "$out/server.log" ||
  { echo "FAIL: the server refused signed messages or checked none"; cat "$out/server.log"; exit 1; }
echo "two_hosts_test: passed"
