#!/usr/bin/env bash
# Installs what is missing, builds the "release" preset and runs the demo.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cmake --preset release
cmake --build --preset release -j "$(nproc)" --target dt_node dt_server dt_ctl dt_launch dt_drill
# The demo exercise (configs/drills/demo.toml): server + 3 nodes whose scenarios create, edit,
# breach and destroy features while vehicles drive; node-1 is killed and restarted; the report
# ends with every process's digest. Runs in a private network namespace: nothing leaves the host.
tests/run_in_netns.sh ./build/release/launcher/dt_drill --drill configs/drills/demo.toml \
  --run-dir run/demo "$@"
