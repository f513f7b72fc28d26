#!/usr/bin/env bash
# Installs what is missing, builds the "release" preset and runs the demo.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cmake --preset release
cmake --build --preset release -j "$(nproc)" --target dt_terrain_demo
./build/release/terrain/dt_terrain_demo "$@"
