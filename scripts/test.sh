#!/bin/sh
# Builds Orbis and runs every test (unit, rendering on llvmpipe, install, benchmark smoke runs).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
build="${ORBIS_BUILD_DIR:-$root/build}"
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir "$build" --output-on-failure --parallel "$jobs" --timeout 600
