#!/bin/sh
# Builds Orbis in a tree of its own under AddressSanitizer and UndefinedBehaviorSanitizer (every
# target, -O1) and runs the test suite there: the unit, rendering (llvmpipe), command-line, example
# and install tests. Left out, as the normal tree runs them already: the benchmarks and their smoke
# run (too slow instrumented), the fuzzers (built with clang and sanitizers of their own) and the
# ThreadSanitizer executables (TSan cannot share a process with ASan). scripts/test.sh runs this
# after the normal suite; run it alone with scripts/test-sanitized.sh.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build="${ORBIS_SANITIZED_BUILD_DIR:-$root/build-asan}"
jobs=$(nproc 2>/dev/null || echo 2)
export CCACHE_BASEDIR="$root"

# -O1: most of -O3's speed for the tests at a fraction of its compile time. Warnings are not errors
# here: GCC warns spuriously under -fsanitize (its manual says so), and the normal tree builds with
# -Werror already.
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-O1 \
  -DCMAKE_C_FLAGS_DEBUG=-O1 -DORBIS_SANITIZE=address,undefined -DORBIS_WARNINGS_AS_ERRORS=OFF \
  -DORBIS_BUILD_BENCHMARKS=OFF
cmake --build "$build" --parallel "$jobs"

# Every report fails its test: ASan and UBSan abort on the first error (the build also passes
# -fno-sanitize-recover=all), and LeakSanitizer runs at exit. Mesa's DRI driver (llvmpipe, with the
# LLVM it links) is preloaded so that it stays loaded until the leak check: EGL unloads it at
# eglTerminate, and the caches it still holds would then be reported from an unknown module that
# no suppression can name. Preloaded, they are reachable from its globals and are not leaks; what
# the driver stack does leak is suppressed by tests/sanitizers/mesa-leaks.supp, nothing else. The
# link-order check is off because the driver comes before the ASan runtime (which it does not
# interpose on); the processes that are not instrumented merely load the driver.
driver=/usr/lib/$(gcc -print-multiarch)/dri/swrast_dri.so
[ -f "$driver" ] && export LD_PRELOAD="$driver"
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:strict_init_order=1:check_initialization_order=1:verify_asan_link_order=0"
export UBSAN_OPTIONS="halt_on_error=1:abort_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$root/tests/sanitizers/mesa-leaks.supp:print_suppressions=0"
ctest --test-dir "$build" --output-on-failure --parallel "$jobs" --timeout 600
