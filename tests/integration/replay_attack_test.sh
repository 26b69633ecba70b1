#!/usr/bin/env bash
# A key holder's captured traffic against a restarted server (issue 44, items
# 1 and 2). A keyed session is logged while `igms-command shutdown` stops its
# server; a fresh keyed server is started, and the log is thrown at it:
#   - igms-replay play with its defaults: the command is left out (said so), the
#     rest is signed as a replay and refused by the server (replayed_session);
#   - igms-replay play --with-commands: the SHUTDOWN is refused (replayed_session);
#   - igms-replay play under another key: no recorded signature holds, nothing is re-signed;
#   - the captured SHUTDOWN datagram, byte for byte, within its minute of
#     freshness: refused as a command of an earlier session;
#   - a server started with --accept-replay takes the replay, and still refuses
#     the replayed SHUTDOWN (another session's token, signed before it started).
# Each server is alive afterwards and stops on a live igms-command shutdown.
#   tests/integration/replay_attack_test.sh BUILD_DIR PORT
set -euo pipefail
build=$(cd "${1:?build dir}" && pwd)
port=${2:?port}
cd "$(dirname "$0")/../.."
source scripts/lib/session.sh
igms_in_netns "$0" "$@"
export IGMS_BUILD=$build
igms_build=$build
work=$(mktemp -d /tmp/igms-replay-attack.XXXXXX)
trap 'igms_stop_all; igms_drop_key; rm -rf "$work"' EXIT
url="udpm://239.255.76.67:$port?ttl=0"
igms_use_key
scene=scenes/puma_obstacle.yaml
fail() { echo "replay_attack_test: FAIL: $*" >&2; exit 1; }

alive_after() {  # PID SECONDS: still running that long after
  sleep "$2"
  kill -0 "$1" 2>/dev/null
}

# 1. The session to capture: logged while a live command stops it.
igms_start_logger "$work/captured.lcmlog" "$url" -q --wait-session-s 2
"$build/server/igms-server" --scene "$scene" --lcm-url "$url" --quiet 2> "$work/first.log" &
first=$!
igms_pids+=($first)
sleep 1.5
"$build/tools/igms-command" --lcm-url "$url" shutdown 2> "$work/command1.log" || fail "the live shutdown: $(cat "$work/command1.log")"
wait "$first" || fail "the first server's exit: $(cat "$work/first.log")"
sleep 0.3
igms_stop_all
n=$("$build/tools/igms-replay" info "$work/captured.lcmlog" | awk '/IGMS_COMMAND/ {print $2}')
[[ ${n:-0} -ge 1 ]] || fail "no command in the captured log"

start_second() {  # LOG [server options]
  local log=$1
  shift
  "$build/server/igms-server" --scene "$scene" --lcm-url "$url" "$@" 2> "$log" &
  second=$!
  igms_pids+=($second)  # stopped on any exit path, a failed check included
  sleep 1.0
}
stop_second() {  # LOG: a live, signed command still stops it
  "$build/tools/igms-command" --lcm-url "$url" shutdown 2>> "$work/command2.log" || fail "the live shutdown of the second server"
  wait "$second" || fail "the second server's exit: $(tail -3 "$1")"
}

# 2. A fresh server; the log played at it with the defaults, then with its commands.
start_second "$work/second.log"
"$build/tools/igms-replay" play "$work/captured.lcmlog" --fast --lcm-url "$url" 2> "$work/play1.log"
grep -q "left out 1 commands" "$work/play1.log" || fail "the default replay did not leave the command out: $(cat "$work/play1.log")"
grep -q "signed as a replay" "$work/play1.log" || fail "the replay did not sign as a replay"
# (the command alone: a burst of 1500 states could crowd it out of the server's socket)
"$build/tools/igms-replay" play "$work/captured.lcmlog" --fast --with-commands --channel IGMS_COMMAND --lcm-url "$url" \
  2> "$work/play2.log"
alive_after "$second" 1.0 || fail "a replayed SHUTDOWN (--with-commands) stopped the fresh server"
# Under another key the recorded signatures do not hold: nothing is re-signed.
igms_new_key "$work/other.key"
if "$build/tools/igms-replay" play "$work/captured.lcmlog" --fast --key-file "$work/other.key" --lcm-url "$url" \
  2> "$work/play_other.log"; then fail "a log signed under another key was replayed"; fi
grep -q "left out [0-9]* events whose recorded signature does not hold" "$work/play_other.log" ||
  fail "the other key's replay did not say what it left out: $(cat "$work/play_other.log")"

# 3. The captured datagram itself, byte for byte: fresh by its clock, from a sender the new server never heard.
sent=$("$build/tests/raw_publish" "$work/captured.lcmlog" IGMS_COMMAND "$url")
[[ $sent -ge 1 ]] || fail "raw_publish sent nothing"
alive_after "$second" 1.0 || fail "the captured signed SHUTDOWN, sent again, stopped the restarted server"
grep -q "command rejected: signed before this server started" "$work/second.log" ||
  fail "the captured SHUTDOWN was not refused as an earlier session's: $(grep -c . "$work/second.log") lines of log"
stop_second "$work/second.log"
grep -Eq "bus: accepted [0-9]+, refused [0-9]+ \(.*replayed_session [1-9]" "$work/second.log" ||
  fail "the server did not count the replay as replayed_session: $(grep 'bus:' "$work/second.log")"
rejected=$(grep -o "commands=[0-9]* rejected=[0-9]*" "$work/second.log" | tail -1)
[[ $rejected =~ rejected=([0-9]+) ]] && ((BASH_REMATCH[1] >= 1)) || fail "no rejected command counted: $rejected"

# 4. A server that takes replays: the states and statuses go in, the old SHUTDOWN still does not.
start_second "$work/third.log" --accept-replay
"$build/tools/igms-replay" play "$work/captured.lcmlog" --fast --with-commands --channel IGMS_COMMAND --lcm-url "$url" \
  2> "$work/play3.log"
alive_after "$second" 1.0 || fail "a replayed SHUTDOWN stopped a server that takes replays"
grep -q "command rejected: \(signed before\|not this session\)" "$work/third.log" ||
  fail "the replayed SHUTDOWN was not refused by the server that takes replays"
stop_second "$work/third.log"
if grep -Eq "replayed_session" "$work/third.log"; then fail "--accept-replay still refused the replay"; fi
echo "replay_attack_test: a replay and a captured SHUTDOWN are refused and counted; live commands work"
