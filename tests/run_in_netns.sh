#!/usr/bin/env bash
# Runs a command inside a private network namespace whose only interface is loopback, with
# multicast routed over it, so exercises and drills never send a packet off this machine.
#   tests/run_in_netns.sh <command> [args...]
# Exits 77 (ctest SKIP_RETURN_CODE) when namespaces are not permitted here.
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: $0 <command> [args...]" >&2
  exit 2
fi
if [[ "${DT_IN_PRIVATE_NETNS:-}" != "1" ]]; then
  # Root uses a plain network namespace; others map themselves to root in a user namespace.
  if unshare -n true 2>/dev/null; then
    flags=(-n)
  elif unshare -rn true 2>/dev/null; then
    flags=(-rn)
  else
    echo "$0: unshare -n is not permitted here (needs root or user namespaces)" >&2
    exit 77
  fi
  DT_IN_PRIVATE_NETNS=1 exec unshare "${flags[@]}" "$0" "$@"
fi
ip link set lo up
ip link set lo multicast on
ip route add 224.0.0.0/4 dev lo
exec "$@"
