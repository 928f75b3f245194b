#!/bin/sh
# Cuts ETOPO5 (the 16-bit PNG of /work/shared/data/terrain/etopo5, or any copy of it) into the
# quantized-mesh tile set shipped in data/terrain/etopo5. The PNG holds grid-registered samples
# (sample (c, r) at 180 W + c/12 degrees, 90 N - r/12 degrees, height = value - 32768): a VRT gives
# GDAL that geotransform (pixel corners half a sample out) and the offset.
# Usage: scripts/make-etopo5-terrain.sh ETOPO5.png OUT-FOLDER [more orbis tile terrain options]
# Needs the orbis command built (build/bin/orbis, or ORBIS=path).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
png=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
out="$2"
shift 2
orbis="${ORBIS:-$root/build/bin/orbis}"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cat > "$scratch/etopo5.vrt" <<VRT
<VRTDataset rasterXSize="4320" rasterYSize="2161">
  <SRS>EPSG:4326</SRS>
  <GeoTransform>-180.041666666666667, 0.0833333333333333333, 0, 90.041666666666667, 0, -0.0833333333333333333</GeoTransform>
  <VRTRasterBand dataType="UInt16" band="1">
    <Offset>-32768</Offset>
    <SimpleSource>
      <SourceFilename relativeToVRT="0">$png</SourceFilename>
      <SourceBand>1</SourceBand>
    </SimpleSource>
  </VRTRasterBand>
</VRTDataset>
VRT
"$orbis" tile terrain "$scratch/etopo5.vrt" --out "$out" --threads 2 --title "ETOPO5" \
  --attribution "ETOPO5, NOAA National Geophysical Data Center" "$@"
