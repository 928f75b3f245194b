#!/bin/sh
# Builds Orbis and runs every test (unit, rendering on llvmpipe, install, benchmark smoke runs, the
# fuzzers for a bounded time, the threading tests under ThreadSanitizer), then the suite again in
# a tree of its own under AddressSanitizer and UndefinedBehaviorSanitizer, less its slowest tests
# (scripts/test-sanitized.sh says what that pass leaves out). ORBIS_SANITIZERS=0 skips the second pass.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
build="${ORBIS_BUILD_DIR:-$root/build}"
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir "$build" --output-on-failure --parallel "$jobs" --timeout 600

[ "${ORBIS_SANITIZERS:-1}" = 0 ] || "$root/scripts/test-sanitized.sh"
