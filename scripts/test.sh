#!/bin/sh
# Builds Orbis and runs every test (unit, rendering on llvmpipe, install, benchmark smoke runs).
# With ORBIS_SANITIZERS=1, then the GL-free tests (core and world: math, tiling, the readers of
# every file format, tile sources and the loader) again in a tree of their own under
# AddressSanitizer and UndefinedBehaviorSanitizer (not yet in CI: its build time on CI's two cores
# is still to be measured against the 30-minute budget).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
build="${ORBIS_BUILD_DIR:-$root/build}"
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir "$build" --output-on-failure --parallel "$jobs" --timeout 600

[ "${ORBIS_SANITIZERS:-0}" = 1 ] || exit 0
sanitized="${ORBIS_SANITIZED_BUILD_DIR:-$root/build-asan}"
werror=OFF
[ "${ORBIS_WERROR:-0}" = 1 ] && werror=ON
export CCACHE_BASEDIR="$root"
# -O1: most of -O3's speed for the tests, a fraction of its compile time.
cmake -S "$root" -B "$sanitized" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-O1 \
  -DORBIS_SANITIZE=address,undefined -DORBIS_WARNINGS_AS_ERRORS=$werror \
  -DORBIS_BUILD_BENCHMARKS=OFF -DORBIS_BUILD_EXAMPLES=OFF
cmake --build "$sanitized" --parallel "$jobs" --target orbis_core_tests orbis_world_tests
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir "$sanitized" --output-on-failure --parallel "$jobs" --timeout 600 \
  -L '^orbis_(core|world)_tests$'
