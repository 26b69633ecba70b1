#!/usr/bin/env bash
# A private bus shared by separate terminals: a named network namespace whose
# only interface is lo, with multicast routed to it (LCM's ttl=0 data and IGMP
# joins never leave the machine), created once and joined by every later
# command. scripts/netns_run.sh is the one-shot kind (one namespace per call:
# what tests use); processes started by two netns_run.sh calls do not hear each
# other, processes started by `bus.sh run` do.
#   scripts/sessions/bus.sh up              create it (idempotent)
#   scripts/sessions/bus.sh run CMD [ARGS]  run CMD on it (creates it when missing)
#   scripts/sessions/bus.sh status          is it there, and what listens on it
#   scripts/sessions/bus.sh port PORT       this machine's 127.0.0.1:PORT reaches the bus's 127.0.0.1:PORT
#                                  (a browser outside opens the viewer's page; Ctrl-C stops)
#   scripts/sessions/bus.sh key             print the path of its bus key
#   scripts/sessions/bus.sh down            remove it and its key (the processes on it keep their sockets)
# The bus is signed: `up` makes it a key (mode 0600, in a private folder of
# this user's, $XDG_RUNTIME_DIR/igms-bus-UID or /tmp/igms-bus-UID, mode 0700,
# refused when someone else made it first) and `run` hands it to the command as
# IGMS_KEY_FILE, unless that is set.
# IGMS_BUS names it (default igms). `ip netns` needs root: as a user, sudo
# enters the namespace and the command runs as you again.
set -euo pipefail
name=${IGMS_BUS:-igms}
sudo=""
[[ $(id -u) -eq 0 ]] || sudo="sudo"

source "$(dirname "$0")/../lib/bus_key.sh"
[[ $name =~ ^[A-Za-z0-9_-]+$ ]] || { echo "bus.sh: IGMS_BUS is a name (letters, digits, '_', '-'), not '$name'" >&2; exit 2; }
key_folder=${XDG_RUNTIME_DIR:-/tmp}/igms-bus-$(id -u)
key_file=$key_folder/$name.key
exists() { [[ -e /run/netns/$name ]]; }
up() {
  igms_private_folder "$key_folder" || exit 1
  [[ -e $key_file ]] || igms_new_key "$key_file"
  exists && return 0
  # Two first calls at once: one makes it, the other waits and finds it (the lock ends with the subshell,
  # so no command started later inherits it).
  (
    flock 9
    exists && exit 0
    $sudo ip netns add "$name"
    $sudo ip -n "$name" link set lo up
    $sudo ip -n "$name" link set lo multicast on
    $sudo ip -n "$name" route add 224.0.0.0/4 dev lo
    echo "bus.sh: private bus '$name' is up (scripts/sessions/bus.sh run CMD joins it; scripts/sessions/bus.sh down removes it)" >&2
  ) 9>"$key_folder/$name.lock"  # in the private folder: no lock file planted as a link in /tmp
}

case "${1:-}" in
  up) up ;;
  run)
    shift
    [[ $# -gt 0 ]] || { echo "usage: $0 run COMMAND [ARGS...]" >&2; exit 2; }
    up
    export IGMS_KEY_FILE=${IGMS_KEY_FILE:-$key_file}
    if [[ -z $sudo ]]; then
      exec ip netns exec "$name" env IGMS_IN_NETNS=1 "$@"
    fi
    exec sudo ip netns exec "$name" sudo -u "$(id -un)" --preserve-env env IGMS_IN_NETNS=1 "$@"
    ;;
  port)
    [[ ${2:-} =~ ^[0-9]+$ ]] || { echo "usage: $0 port PORT" >&2; exit 2; }
    exists || { echo "bus.sh: no bus '$name' (scripts/sessions/bus.sh up)" >&2; exit 1; }
    echo "bus.sh: http://127.0.0.1:$2/ reaches port $2 on bus '$name' (Ctrl-C stops)" >&2
    enter="ip netns exec $name"
    [[ -z $sudo ]] || enter="sudo $enter"
    exec socat "TCP-LISTEN:$2,bind=127.0.0.1,reuseaddr,fork" "EXEC:$enter socat STDIO TCP\:127.0.0.1\:$2"
    ;;
  status)
    if exists; then
      echo "bus '$name': up"
      $sudo ip netns exec "$name" ss -uanp 2>/dev/null | tail -n +2 || true
    else
      echo "bus '$name': down"
      exit 1
    fi
    ;;
  key)
    [[ -e $key_file ]] || { echo "bus.sh: no key for bus '$name' (scripts/sessions/bus.sh up)" >&2; exit 1; }
    echo "$key_file"
    ;;
  down)
    if exists; then $sudo ip netns del "$name"; echo "bus.sh: private bus '$name' removed" >&2; fi
    rm -f "$key_file"
    ;;
  *)
    echo "usage: $0 up|run COMMAND...|port PORT|status|key|down   (IGMS_BUS names the bus; default igms)" >&2
    exit 2
    ;;
esac
