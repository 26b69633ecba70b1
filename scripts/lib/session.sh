# A session over the bus, for the scripts that run one (source it):
#   source scripts/lib/session.sh
#   igms_in_netns "$0" "$@"                       # re-runs the script in a private network namespace
#   igms_start_logger LOG URL [logger options]    # background; returns once it listens
#   igms_start_server SCENE URL [server options]  # background
#   igms_run_client SCENE DEVICE URL [client options]   # foreground, until its duration or script ends
#   igms_start_client SCENE DEVICE URL [client options] # background (another hand); igms_wait_clients waits
#   igms_stop_all                                 # newest first: server, then logger (it hears the end)
# Every process started here is stopped on any exit path (a trap on EXIT,
# INT and TERM), so a failing script leaves nothing running. The bus is
# signed: the processes get IGMS_KEY_FILE, the caller's or a new key made for
# this session (scripts/lib/bus_key.sh, removed at exit).
# Binaries come from ${IGMS_BUILD:-build}.
source "$(dirname "${BASH_SOURCE[0]}")/bus_key.sh"

igms_build=${IGMS_BUILD:-build}
igms_pids=()
igms_client_pids=()

igms_in_netns() {
  if [[ "${IGMS_IN_NETNS:-}" != "1" ]]; then exec scripts/netns_run.sh "$@"; fi
}

igms_stop() {  # PID: SIGTERM, then wait for it
  kill "$1" 2>/dev/null || true
  wait "$1" 2>/dev/null || true
}

igms_stop_all() {
  local i
  for ((i = ${#igms_pids[@]} - 1; i >= 0; i--)); do
    igms_stop "${igms_pids[i]}"
    # the next one (the logger) gets a moment for the last messages
    ((i > 0)) && sleep 0.3
  done
  igms_pids=()
}
trap 'igms_stop_all; igms_drop_key' EXIT
trap 'igms_stop_all; igms_drop_key; exit 130' INT TERM

igms_start_logger() {  # LOG URL [options]
  igms_use_key
  local log=$1 url=$2
  shift 2
  rm -f "$log"
  "$igms_build/tools/igms-logger" -o "$log" --lcm-url "$url" "$@" &
  igms_pids+=($!)
  sleep 0.3
}

igms_start_server() {  # SCENE URL [options]
  igms_use_key
  local scene=$1 url=$2
  shift 2
  "$igms_build/server/igms-server" --scene "$scene" --lcm-url "$url" "$@" &
  igms_pids+=($!)
  sleep 0.3
}

igms_run_client() {  # SCENE DEVICE URL [options]
  igms_use_key
  local scene=$1 device=$2 url=$3
  shift 3
  "$igms_build/haptic_client/igms-haptic" --scene "$scene" --device "$device" --lcm-url "$url" "$@"
}

igms_start_client() {  # SCENE DEVICE URL [options]: a client in the background (another hand)
  igms_use_key
  local scene=$1 device=$2 url=$3
  shift 3
  "$igms_build/haptic_client/igms-haptic" --scene "$scene" --device "$device" --lcm-url "$url" "$@" &
  igms_client_pids+=($!)
  igms_pids+=($!)
}

igms_wait_clients() {  # the background clients' ends; fails when one failed
  local pid rc=0
  for pid in "${igms_client_pids[@]}"; do wait "$pid" || rc=$?; done
  igms_client_pids=()
  return $rc
}
