#!/usr/bin/env bash
# The README's multi-terminal workflow, as separate commands: a logger, a
# server and igms-spy each started on their own by `scripts/sessions/bus.sh run` hear
# each other on the shared private bus, and a viewer on it serves a browser
# outside through `scripts/sessions/bus.sh port`; and tools that hear nothing say so:
# a spy and a logger in one-shot namespaces of their own print "nothing heard"
# and exit 1, as does `igms-replay play` when its filter matches nothing.
#   tests/integration/shared_bus_test.sh BUILD_DIR PORT
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "$1" && pwd)
url="udpm://239.255.76.67:$2?ttl=0"
export IGMS_BUS=igms-test-$$
tmp=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  pkill -f "igms-viewer --lcm-url $url" 2>/dev/null || true
  wait 2>/dev/null || true
  "$src/scripts/sessions/bus.sh" down 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT
cd "$src"
fail() { echo "shared_bus_test: $*" >&2; exit 1; }

# Three "terminals".
scripts/sessions/bus.sh run "$build/tools/igms-logger" "$tmp/session.lcmlog" --lcm-url "$url" --duration 4 -q & pids+=($!)
sleep 0.3
scripts/sessions/bus.sh run "$build/server/igms-server" --scene scenes/puma_wall.yaml --lcm-url "$url" --duration 3 --quiet &
pids+=($!)
sleep 1
scripts/sessions/bus.sh run "$build/tools/igms-spy" --lcm-url "$url" --once --json > "$tmp/spy.json"
wait "${pids[0]}" || fail "the logger failed"
python3 - "$tmp/spy.json" <<'PY'
import json, sys
spy = json.load(open(sys.argv[1]))
assert spy.get("IGMS_ROBOT_STATE", {}).get("rate_hz", 0) > 500, spy
print("spy on the shared bus: IGMS_ROBOT_STATE at %.0f Hz" % spy["IGMS_ROBOT_STATE"]["rate_hz"])
PY
events=$("$build/tools/igms-replay" info "$tmp/session.lcmlog" | sed -n 's/.*: \([0-9]*\) events over.*/\1/p')
echo "logger on the shared bus: $events events"
(( events > 1000 )) || fail "the logger recorded $events events"

# igms-spy --json stays JSON whatever a channel is called (quotes, backslashes: it once printed them raw).
python=$("$src/scripts/setup/python_env.sh")
scripts/sessions/bus.sh run "$python" -c '
import lcm, sys, time
bus = lcm.LCM(sys.argv[1])
end = time.time() + 2.0
while time.time() < end:
    bus.publish(sys.argv[2], b"not an igms message")
    time.sleep(0.01)' "$url" 'we"ird\chan' & pids+=($!)
sleep 0.3
scripts/sessions/bus.sh run "$build/tools/igms-spy" --lcm-url "$url" --once --json > "$tmp/spy_odd.json" || fail "spy heard nothing"
python3 - "$tmp/spy_odd.json" <<'PY'
import json, sys
spy = json.load(open(sys.argv[1]))
odd = spy['we"ird\\chan']
assert odd["count"] > 10 and odd["type"] == "", odd
print("spy --json with the channel we\"ird\\chan: valid JSON, %d messages" % odd["count"])
PY

# A browser outside the bus reaches a viewer on it (scripts/sessions/bus.sh port).
if [[ -x $build/tools/igms-viewer ]]; then
  web_port=$(( $2 + 10000 ))
  scripts/sessions/bus.sh run "$build/tools/igms-viewer" --lcm-url "$url" --port "$web_port" >/dev/null 2>&1 & pids+=($!)
  sleep 0.5
  scripts/sessions/bus.sh port "$web_port" 2>/dev/null & pids+=($!)
  for _ in $(seq 50); do python3 -c "import sys, urllib.request; open(sys.argv[2], 'wb').write(urllib.request.urlopen(sys.argv[1], timeout=2).read())" "http://127.0.0.1:$web_port/" "$tmp/page.html" 2>/dev/null && break; sleep 0.1; done
  grep -q "igms live view" "$tmp/page.html" || fail "the viewer's page did not come through scripts/sessions/bus.sh port"
  echo "the viewer's page through scripts/sessions/bus.sh port $web_port: $(wc -c < "$tmp/page.html") bytes"
  pkill -f "TCP-LISTEN:$web_port" || true
fi

# Loud silence: one-shot namespaces hear nothing.
set +e
scripts/netns_run.sh "$build/tools/igms-spy" --lcm-url "$url" --once --window 0.5 >/dev/null 2>"$tmp/spy.err"
rc=$?
set -e
cat "$tmp/spy.err"
[[ $rc -eq 1 ]] && grep -q "nothing heard" "$tmp/spy.err" || fail "a spy that heard nothing exited $rc"
set +e
scripts/netns_run.sh "$build/tools/igms-logger" "$tmp/empty.lcmlog" --lcm-url "$url" --duration 1.5 --silence-s 1 -q \
  2>"$tmp/logger.err"
rc=$?
set -e
cat "$tmp/logger.err"
[[ $rc -eq 1 ]] && grep -q "nothing heard" "$tmp/logger.err" && grep -q "the log is empty" "$tmp/logger.err" ||
  fail "a logger that heard nothing exited $rc"
scripts/netns_run.sh "$build/tools/igms-logger" "$tmp/empty2.lcmlog" --lcm-url "$url" --duration 0.5 -q --allow-empty ||
  fail "--allow-empty did not allow an empty log"
set +e
scripts/netns_run.sh "$build/tools/igms-replay" play "$tmp/session.lcmlog" --lcm-url "$url" --fast --channel NOPE \
  2>"$tmp/play.err"
rc=$?
set -e
cat "$tmp/play.err"
[[ $rc -eq 1 ]] && grep -q "nothing in" "$tmp/play.err" || fail "play of nothing exited $rc"
echo "shared_bus_test: ok"
