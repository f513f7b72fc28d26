#!/usr/bin/env bash
# Installs what is missing, builds the "ci" preset and runs the whole test suite.
#   scripts/test.sh            # every test (unit, integration, drill)
#   scripts/test.sh -L unit    # extra arguments go to ctest
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cmake --preset ci
cmake --build --preset ci -j "$(nproc)"
ctest --preset ci -j "$(nproc)" "$@"
