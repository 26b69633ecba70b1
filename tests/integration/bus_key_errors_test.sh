#!/usr/bin/env bash
# What a person sees with a missing, wrong or bad bus key: one line naming the
# problem, from the program that has it. A keyed server with a client that has
# no key: the server refuses its unsigned inputs and says why. A client with
# another key: it refuses every state, says why, and gives up waiting with a
# hint. A key file others can read, or that is not a key: an error naming the
# file, exit 2.
#   tests/integration/bus_key_errors_test.sh BUILD_DIR PORT
set -euo pipefail
build=$(cd "${1:?build dir}" && pwd)
port=${2:?port}
cd "$(dirname "$0")/../.."
source scripts/lib/session.sh
igms_in_netns "$0" "$@"
work=$(mktemp -d /tmp/igms-keyerr.XXXXXX)
trap 'igms_stop_all; rm -rf "$work"' EXIT
url="udpm://239.255.76.67:$port?ttl=0"
scene=scenes/puma_obstacle.yaml
igms_new_key "$work/server.key"
igms_new_key "$work/other.key"
fails=0
expect() {  # FILE TEXT WHAT
  if grep -qF -- "$2" "$1"; then echo "ok    $3"; else echo "FAIL  $3: no '$2' in:"; cat "$1"; fails=$((fails + 1)); fi
}

"$build/server/igms-server" --scene "$scene" --lcm-url "$url" --quiet --key-file "$work/server.key" \
  2> "$work/server.log" &
igms_pids+=($!)
sleep 0.5
# No key: the client takes the signed states unchecked (and says so); the server refuses its inputs.
"$build/haptic_client/igms-haptic" --scene "$scene" --device scripted:scenes/paper_push.yaml --lcm-url "$url" \
  --duration 1 --quiet 2> "$work/nokey.log" || true
expect "$work/nokey.log" "igms-haptic: the bus is unauthenticated (no --key-file" "a program without a key says the bus is unauthenticated"
expect "$work/nokey.log" "are signed but this program has no bus key: pass --key-file" "the client without the key says the bus is signed"
# Another key: every state refused, and the wait for the server ends with a hint.
"$build/haptic_client/igms-haptic" --scene "$scene" --device scripted:scenes/paper_push.yaml --lcm-url "$url" \
  --duration 1 --quiet --connect-timeout 2 --key-file "$work/other.key" 2> "$work/otherkey.log" && rc=0 || rc=$?
expect "$work/otherkey.log" "fails its signature check: signed with another key (a different --key-file?) or forged" "a client with another key says why it refuses"
expect "$work/otherkey.log" "that passed the message check (see above: a missing or wrong --key-file?)" "and why it found no server"
[[ $rc == 3 ]] && echo "ok    it exits 3 (no server)" || { echo "FAIL  exit $rc, not 3"; fails=$((fails + 1)); }
igms_stop_all
expect "$work/server.log" "igms-server: refused a message on IGMS_HAPTIC_INPUT: it is unsigned: its sender has no bus key" "the server says why it refuses the keyless client's inputs"
expect "$work/server.log" "igms-server: bus: accepted 0, refused" "the server counted them and applied none"

# Bad key files: named, with the problem, exit 2.
chmod 644 "$work/other.key"
"$build/server/igms-server" --scene "$scene" --lcm-url "$url" --key-file "$work/other.key" 2> "$work/open.log" && rc=0 || rc=$?
expect "$work/open.log" "other.key: readable by others (mode 644); chmod 600 it" "a key others can read is refused"
[[ $rc == 2 ]] && echo "ok    exit 2" || { echo "FAIL  exit $rc, not 2"; fails=$((fails + 1)); }
(umask 077 && echo "not a key" > "$work/bad.key")
IGMS_KEY_FILE=$work/bad.key "$build/tools/igms-command" --lcm-url "$url" pause 2> "$work/bad.log" && rc=0 || rc=$?
expect "$work/bad.log" "bad.key: holds 9 characters, not the key's 64 hex digits" "a file that is not a key is named (IGMS_KEY_FILE too)"
[[ $rc == 2 ]] && echo "ok    exit 2" || { echo "FAIL  exit $rc, not 2"; fails=$((fails + 1)); }
((fails == 0)) && echo "bus_key_errors_test: passed" || { echo "bus_key_errors_test: $fails failed"; exit 1; }
