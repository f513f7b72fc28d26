#!/usr/bin/env bash
# Regenerates docs/images/vehicle-crater.png and docs/images/vehicle-fall.png (docs/vehicles.md
# "Pictures"): builds dt_vehicle_pictures in the "release" preset and runs it. The renderer is
# OSMesa on the CPU: no display or GPU is needed, and the same build gives the same pixels.
set -euo pipefail
cd "$(dirname "$0")/.."

cmake --preset release >/dev/null
cmake --build --preset release -j 2 --target dt_vehicle_pictures
./build/release/runtime/dt_vehicle_pictures --out docs/images "$@"
