#!/bin/sh
# Builds Orbis in a tree of its own under AddressSanitizer and UndefinedBehaviorSanitizer (-O1) and
# runs the test suite there: the unit and rendering (llvmpipe) tests of core, world, renderer and
# scene, the chapter examples against their golden images, the command-line tests and the install
# test. scripts/test.sh runs this after the normal suite; run it alone with
# scripts/test-sanitized.sh, and with --all for the slow tests it leaves out.
#
# Left out, as the normal tree runs them already: the benchmarks and their smoke run (too slow
# instrumented), the fuzzers (built with clang and sanitizers of their own) and the ThreadSanitizer
# executables (TSan cannot share a process with ASan). Left out to keep CI within its 30 minutes
# (docs/building.md has the figures), unless --all: the slowest tests, each a larger or repeated
# run of code that quicker sanitized tests cover (listed in `slow` below).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build="${ORBIS_SANITIZED_BUILD_DIR:-$root/build-asan}"
jobs=$(nproc 2>/dev/null || echo 2)
export CCACHE_BASEDIR="$root"
# This tree compiles with -g1, for which ccache hashes the working directory too: without this, a
# fresh clone misses the cache for every source and rebuilds the whole tree (about 1,700 CPU
# seconds). The price: a report's source paths may name the folder that first compiled the file.
export CCACHE_NOHASHDIR=1

all=no
case "${1:-}" in
  --all) all=yes ;;
  "") ;;
  *) echo "usage: scripts/test-sanitized.sh [--all]" >&2; exit 2 ;;
esac

# The slowest tests instrumented (seconds under ASan on the two-core machine), and what covers
# their code in the pass: the 1:10m countries (150 s; the 1:50m ones), 10,000 random views of the
# tile selection (75 s; the other selection tests), the most-detailed heights at every DEM pixel
# (60 + 50 s; the other terrain-query tests), ear clipping of 100,000-vertex rings (60 s; the other
# earClip tests), the precision suites again without two GL extensions (60 + 5 s) and the
# renderer suite again through a GLFW window on Xvfb (30 s; the window backend's own tests stay).
slow='Natural Earth 1:10m|Tile selection over 10,000 random views|Most-detailed heights from .* cut from a DEM'
slow="$slow|rings of 100,000 vertices|without GL_ARB_clip_control|through a GLFW window on Xvfb"
[ "$all" = yes ] && slow='^$' # matches no test name

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
# Left out always: the sparse-texture tests (label sparse), which run on another Mesa (zink, from
# scripts/install-sparse-mesa.sh) that the preloaded llvmpipe of the system's would clash with;
# the normal tree runs them.
ctest --test-dir "$build" --output-on-failure --parallel "$jobs" --timeout 600 -E "$slow" -LE sparse
