#!/bin/sh
# Installs missing dependencies, then configures and builds Orbis into build/ (Release, ccache).
# Usage: scripts/build.sh [extra cmake -D options]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"

build="${ORBIS_BUILD_DIR:-$root/build}"
werror=OFF
[ "${ORBIS_WERROR:-0}" = 1 ] && werror=ON
jobs=$(nproc 2>/dev/null || echo 2)
# Paths relative to the checkout, so clones and worktrees share one compiler cache.
export CCACHE_BASEDIR="$root"

cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DORBIS_WARNINGS_AS_ERRORS=$werror "$@"
cmake --build "$build" --parallel "$jobs"
