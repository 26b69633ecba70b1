#!/usr/bin/env bash
# Run a command in a private network namespace whose only interface is lo, with
# multicast routed to lo: LCM's udpm:// traffic (ttl=0) and its IGMP joins never
# leave this machine. Every process that opens a udpm:// socket runs under this.
#   scripts/netns_run.sh COMMAND [ARGS...]
set -euo pipefail
if [[ $# -eq 0 ]]; then
  echo "usage: $0 COMMAND [ARGS...]" >&2
  exit 2
fi
if [[ "${IGMS_IN_NETNS:-}" == "1" ]]; then
  exec "$@"  # already inside
fi
# unshare -n needs root (or user namespaces); -r maps us to root inside one.
flags=(-n)
if [[ $(id -u) -ne 0 ]]; then flags=(-r -n); fi
exec unshare "${flags[@]}" -- env IGMS_IN_NETNS=1 bash -c '
  set -e
  ip link set lo up
  ip link set lo multicast on
  ip route add 224.0.0.0/4 dev lo
  exec "$@"' igms-netns "$@"
