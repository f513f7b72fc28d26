#!/usr/bin/env bash
# Installs what is missing, builds the "release" preset and runs the demo with its live view.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cmake --preset release
cmake --build --preset release -j "$(nproc)" --target dt_node dt_server dt_ctl dt_launch dt_drill \
  dt_view dt_dis
# The demo exercise (configs/drills/demo.toml): server + 3 nodes whose scenarios create, edit,
# breach and destroy features while vehicles drive; node-1 is killed and restarted; the report
# ends with every process's digest. Runs in a private network namespace: nothing leaves the host.
# The live view (docs/view.md) runs beside the drill in that namespace; scripts/netns_relay.py
# brings its port to this host's 127.0.0.1, so the printed URL opens in any local browser.
# The DIS gateway (docs/dis.md) runs there too; tshark, when installed, records its UDP/3000
# traffic to run/demo/dis.pcap (open it in Wireshark: every vehicle and feature as DIS PDUs).
port=8480
tests/run_in_netns.sh bash -c '
  set -euo pipefail
  ./build/release/launcher/dt_drill --drill configs/drills/demo.toml --run-dir run/demo "$@" &
  drill=$!
  # The drill makes run/demo afresh: the view starts once the server is up in it.
  until [[ -S run/demo/server.sock ]]; do kill -0 $drill 2>/dev/null || break; sleep 0.2; done
  ./build/release/view/dt_view --config configs/exercises/demo.toml --run-dir run/demo \
    > run/demo-view.log 2>&1 &
  view=$!
  ./build/release/dis/dt_dis --config configs/exercises/demo.toml --run-dir run/demo \
    > run/demo-dis.log 2>&1 &
  dis=$!
  capture=
  if command -v tshark > /dev/null; then
    tshark -i lo -f "udp port 3000" -w run/demo/dis.pcap -q > run/demo-tshark.log 2>&1 &
    capture=$!
  fi
  rc=0
  wait $drill || rc=$?
  for p in $view $dis $capture; do kill -TERM $p 2>/dev/null || true; done
  for p in $view $dis $capture; do wait $p || true; done
  [[ -z $capture ]] || echo "demo: the DIS traffic is in run/demo/dis.pcap (docs/dis.md)"
  exit $rc
' demo "$@" &
netns=$!
python3 scripts/netns_relay.py "$netns" "$port" &
relay=$!
trap 'kill $relay 2>/dev/null || true' EXIT
echo "demo: the live view is at http://127.0.0.1:$port/ (open it in a browser on this host)"
wait $netns
