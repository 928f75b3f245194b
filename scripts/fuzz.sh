#!/bin/sh
# Fuzzes one of Orbis's readers: builds its libFuzzer target from tests/fuzz/ with clang (libFuzzer,
# AddressSanitizer, UndefinedBehaviorSanitizer) and runs it for a bounded time from a seed corpus.
# Targets: scene (the scene-file and camera-path parsers, seeded with data/scenes/*.json and
# data/paths/*.json), tms (tilemapresource.xml, seeded with data/imagery/*/tilemapresource.xml),
# tiles (the JPEG, PNG and WebP tile decoders, seeded with tests/fuzz/seeds/tiles), terrain (the
# quantized-mesh, heightmap-1.0, height-image and .hgt decoders and layer.json, seeded with
# tests/fuzz/seeds/terrain), geojson (GeoJSON and TopoJSON, their polygons triangulated, seeded
# with tests/fuzz/seeds/geojson), csv (CSV points, seeded with tests/fuzz/seeds/csv and
# data/scenes/*.csv), gltf (glTF and glb models, seeded with data/models). Exit status: 0 no crash,
# 1 a crash (input saved in the build folder), 77 no usable clang here (CTest reports the test as
# skipped).
# Usage: scripts/fuzz.sh [--target scene|tms|tiles|terrain|geojson|csv|gltf] [--build-dir DIR] [--seconds N] [more libFuzzer options]
# Environment: ORBIS_FUZZ_CXX (default clang++-14, else clang++).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build/fuzz"
seconds=30
target=scene
while [ $# -gt 0 ]; do
  case "$1" in
    --target) target="$2"; shift 2 ;;
    --build-dir) build="$2"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    *) break ;;
  esac
done

# Each target: its sources (the reader and what it uses from core; nothing that needs OpenGL or
# GeographicLib), the libraries it links, its seeds and its dictionary.
libraries=""
companions=""
dictionary=""
workdir=""
case "$target" in
  scene)
    sources="tests/fuzz/SceneParserFuzz.cpp world/src/SceneFile.cpp world/src/JsonLocator.cpp
      world/src/JsonText.cpp world/src/Diagnostics.cpp world/src/CsvPoints.cpp world/src/FileAccess.cpp
      world/src/DepthStrategy.cpp core/src/SunPosition.cpp core/src/Ellipsoid.cpp core/src/Math.cpp
      world/src/CameraKeyframe.cpp core/src/Transforms.cpp core/src/IntersectionTests.cpp scene/src/Camera.cpp
      scene/src/CameraControllers.cpp"
    seeds="$root/data/scenes/*.json $root/data/paths/*.json"
    dictionary="-dict=$root/tests/fuzz/scene.dict"
    workdir="$root/data/scenes" # where the seeds' relative paths lead
    ;;
  tms)
    sources="tests/fuzz/TileMapResourceFuzz.cpp world/src/TileMapResource.cpp world/src/XmlScanner.cpp
      world/src/FileAccess.cpp world/src/Diagnostics.cpp core/src/TilingScheme.cpp core/src/GeodeticExtent.cpp core/src/Ellipsoid.cpp
      core/src/Math.cpp"
    seeds="$root/data/imagery/*/tilemapresource.xml"
    dictionary="-dict=$root/tests/fuzz/tms.dict"
    ;;
  tiles)
    sources="tests/fuzz/TileDecoderFuzz.cpp world/src/ImageCodec.cpp world/src/FileAccess.cpp world/src/Diagnostics.cpp"
    libraries="-lturbojpeg -lspng -lwebp"
    seeds="$root/tests/fuzz/seeds/tiles/*.*"
    ;;
  terrain)
    sources="tests/fuzz/TerrainDecoderFuzz.cpp world/src/TerrainCodec.cpp world/src/TerrainLayer.cpp
      world/src/JsonLocator.cpp world/src/ImageCodec.cpp world/src/FileAccess.cpp world/src/Diagnostics.cpp
      core/src/TilingScheme.cpp core/src/GeodeticExtent.cpp core/src/Ellipsoid.cpp core/src/Math.cpp"
    libraries="-lturbojpeg -lspng -lwebp -lz"
    seeds="$root/tests/fuzz/seeds/terrain/*"
    ;;
  geojson)
    sources="tests/fuzz/GeoJsonFuzz.cpp world/src/GeoJson.cpp world/src/TopoJsonDocument.cpp world/src/RingConvention.cpp
      world/src/JsonText.cpp world/src/JsonLocator.cpp world/src/Diagnostics.cpp world/src/FileAccess.cpp
      core/src/EllipsoidPolygon.cpp core/src/EarClipping.cpp core/src/PolygonCleanup.cpp core/src/PointIndex.cpp core/src/SegmentPairs.cpp
      core/src/RobustPredicates.cpp core/src/TriangleMeshSubdivision.cpp core/src/EllipsoidTangentPlane.cpp
      core/src/Ellipsoid.cpp core/src/Math.cpp"
    seeds="$root/tests/fuzz/seeds/geojson/*"
    ;;
  csv)
    sources="tests/fuzz/CsvPointsFuzz.cpp world/src/CsvPoints.cpp world/src/Diagnostics.cpp world/src/FileAccess.cpp"
    seeds="$root/tests/fuzz/seeds/csv/* $root/data/scenes/*.csv"
    ;;
  gltf)
    sources="tests/fuzz/GltfModelFuzz.cpp world/src/GltfModel.cpp world/src/TinyGltf.cpp world/src/JsonText.cpp
      world/src/JsonLocator.cpp world/src/Diagnostics.cpp world/src/FileAccess.cpp core/src/Math.cpp"
    libraries="-lstb"
    seeds="$root/data/models/*.gltf $root/data/models/*.glb"
    companions="$root/data/models/*.bin $root/data/models/*.png" # the .gltf seed's buffer and image
    ;;
  *)
    echo "fuzz: unknown target $target (scene, tms, tiles, terrain, geojson, csv or gltf)"
    exit 2
    ;;
esac
# Objects are shared by the targets (the same flags for all), so that a source several readers use
# is compiled once.
objectDir="$build/objects"
build="$build/$target"
[ -n "$workdir" ] || workdir="$build"

cxx="${ORBIS_FUZZ_CXX:-}"
if [ -z "$cxx" ]; then
  for candidate in clang++-14 clang++; do
    if command -v "$candidate" >/dev/null 2>&1; then cxx="$candidate"; break; fi
  done
fi
if [ -z "$cxx" ]; then
  echo "fuzz: no clang++ found (scripts/install-deps.sh installs clang-14); skipped"
  exit 77
fi

flags="-std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all
  -I$root/core/include -I$root/world/include -I$root/scene/include -isystem /usr/include/stb"
launcher=""
command -v ccache >/dev/null 2>&1 && launcher=ccache

mkdir -p "$objectDir" "$build/corpus"
binary="$build/${target}_fuzz"
objects=""
for source in $sources; do
  object="$objectDir/$(echo "$source" | tr / _).o"
  objects="$objects $object"
  # Recompile when the source or any header it may include changed.
  if [ ! -f "$object" ] || [ -n "$(find "$root/$source" "$root/core/include" "$root/world/include" "$root/world/src" "$root/scene/include" \
       -newer "$object" -type f 2>/dev/null | head -n 1)" ]; then
    # Written under a name of its own and renamed: targets fuzzed at once may compile it together.
    # shellcheck disable=SC2086
    if ! $launcher "$cxx" $flags -c "$root/$source" -o "$object.$$.tmp"; then
      rm -f "$object.$$.tmp"
      echo "fuzz: compiling $source with $cxx failed"
      exit 1
    fi
    mv -f "$object.$$.tmp" "$object"
  fi
done
# shellcheck disable=SC2086
if ! "$cxx" $flags $objects $libraries -o "$binary"; then
  echo "fuzz: linking failed (is libclang-rt-14-dev installed?)"
  exit 1
fi

# Seeds numbered, as several share a name (every tilemapresource.xml).
count=0
for seed in $seeds; do
  count=$((count + 1))
  cp "$seed" "$build/corpus/seed-$count-$(basename "$seed")"
done
for companion in $companions; do
  cp "$companion" "$build/"
done
cd "$workdir"
echo "fuzz: running $binary for $seconds s"
# shellcheck disable=SC2086
# libFuzzer's own exit codes for a crash (77) and a timeout (70) would read as "skipped" in CTest.
exec "$binary" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
  -error_exitcode=1 -timeout_exitcode=1 \
  $dictionary -artifact_prefix="$build/" "$@" "$build/corpus"
