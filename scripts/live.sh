#!/usr/bin/env bash
# A person's seat: the server (realtime), the live view and the browser as the
# haptic device, on one machine. Prints the URL to open.
#   bash scripts/live.sh [SCENE] [--seconds N]
#     SCENE      default scenes/puma_obstacle.yaml (push and pull on the PUMA)
#     --seconds  stop after N seconds (default: until Ctrl-C)
# Environment:
#   IGMS_LIVE_PORT       the device page (default 8081; its URL carries the session's token)
#   IGMS_LIVE_VIEW_PORT  the watch-only view, igms-viewer (default 8080)
#   IGMS_LIVE_BIND       the address the pages are served on (default 127.0.0.1)
#
# The bus stays inside a private network namespace (ttl=0, as every igms run);
# the two web ports reach this machine's network through socat and a UNIX
# socket, which namespaces share. Installs and builds first (scripts/setup/setup.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
scene=scenes/puma_obstacle.yaml
seconds=0
while (($#)); do
  case $1 in
    --seconds) seconds=$2; shift 2 ;;
    --inner) shift; break ;;
    -h|--help) sed -n 2,15p "$0"; exit 0 ;;
    *) scene=$1; shift ;;
  esac
done
device_port=${IGMS_LIVE_PORT:-8081}
view_port=${IGMS_LIVE_VIEW_PORT:-8080}
bind=${IGMS_LIVE_BIND:-127.0.0.1}
url="udpm://239.255.76.67:7667?ttl=0"
build=${IGMS_BUILD:-build}

if [[ "${1:-}" == "" ]]; then
  # --- this machine's side: set up, bridge the two ports, run the session in a namespace ---
  [[ -f "$scene" ]] || { echo "live: no scene $scene" >&2; exit 2; }
  [[ -n "${IGMS_LIVE_NO_SETUP:-}" ]] || scripts/setup/setup.sh >/dev/null  # (tests: already built)
  sockets=$(mktemp -d /tmp/igms-live.XXXXXX)
  pids=()
  cleanup() {
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    wait 2>/dev/null || true
    rm -rf "$sockets"
  }
  trap cleanup EXIT
  trap 'exit 130' INT TERM
  # A signed bus: a new key for this seat's processes unless IGMS_KEY_FILE names one (removed with $sockets).
  source scripts/lib/bus_key.sh
  if [[ -z ${IGMS_KEY_FILE:-} ]]; then
    igms_new_key "$sockets/bus.key"
    export IGMS_KEY_FILE=$sockets/bus.key
  fi
  for pair in "$device_port:device" "$view_port:view"; do
    socat "TCP-LISTEN:${pair%%:*},bind=$bind,reuseaddr,fork" "UNIX-CONNECT:$sockets/${pair##*:}.sock" &
    pids+=($!)
  done
  host=$bind
  [[ $bind == 0.0.0.0 ]] && host=$(hostname -I 2>/dev/null | awk '{print $1}')
  scripts/netns_run.sh bash "$0" --inner "$sockets" "$scene" "$seconds" "$host" &
  pids+=($!)
  wait "${pids[-1]}"
  exit $?
fi

# --- inside the namespace: server, web device, viewer, and the socket ends of the bridge ---
sockets=$1 scene=$2 seconds=$3 host=$4
pids=()
stop_all() {
  local i
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill "${pids[i]}" 2>/dev/null || true; wait "${pids[i]}" 2>/dev/null || true; done
}
trap stop_all EXIT
trap 'exit 130' INT TERM
out=out/live
# The device URL carries the page's token: its files are this user's alone (another local account
# reading it could drive the robot).
umask 077
mkdir -p "$out"
chmod 700 "$out"
rm -f "$out/device.url" "$out/viewer.url"  # made anew under the umask (a redirect keeps an old file's mode)
"$build/server/igms-server" --scene "$scene" --lcm-url "$url" --quiet &
pids+=($!)
"$build/tools/igms-viewer" --lcm-url "$url" --port "$view_port" > "$out/viewer.url" 2> "$out/viewer.log" &
pids+=($!)
"$build/haptic_client/igms-haptic" --scene "$scene" --device "web:$device_port" --lcm-url "$url" \
  > "$out/device.url" 2> "$out/haptic.log" &
pids+=($!)
for _ in $(seq 50); do [[ -s "$out/device.url" && -s "$out/viewer.url" ]] && break; sleep 0.1; done
socat "UNIX-LISTEN:$sockets/device.sock,fork" "TCP:127.0.0.1:$device_port" &
pids+=($!)
socat "UNIX-LISTEN:$sockets/view.sock,fork" "TCP:127.0.0.1:$view_port" &
pids+=($!)
token=$(sed -n 's/.*token=\([0-9a-f]*\).*/\1/p' "$out/device.url")
echo "live: $scene"
echo "  push and pull it (your mouse is the device): http://$host:$device_port/#token=$token"
echo "  watch only:                                  http://$host:$view_port/"
echo "  logs: $out/ (haptic.log, viewer.log). Ctrl-C stops everything."
if [[ $seconds != 0 ]]; then sleep "$seconds"; else while kill -0 "${pids[0]}" 2>/dev/null; do sleep 1; done; fi
