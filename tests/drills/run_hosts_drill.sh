#!/usr/bin/env bash
# Runs a drill in hosts mode (dt_drill --hosts lan|wan): dt_drill makes a network namespace per
# process on bridges of its own (10.77.0.0/16, never routed out) and removes them at the end.
#   tests/drills/run_hosts_drill.sh <dt_drill> [args...]
# Exits 77 (ctest SKIP_RETURN_CODE) where it cannot make network namespaces (not root).
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: $0 <dt_drill> [args...]" >&2
  exit 2
fi
if [[ "$(id -u)" != "0" ]] || ! command -v ip >/dev/null || ! command -v tc >/dev/null; then
  echo "$0: hosts mode needs root, ip and tc (iproute2)" >&2
  exit 77
fi
exec "$@"
