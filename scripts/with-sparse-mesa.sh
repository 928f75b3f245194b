#!/bin/sh
# Runs a command on the Mesa that scripts/install-sparse-mesa.sh unpacked in .deps/sparse-mesa: the
# zink driver over lavapipe (OpenGL on Vulkan, both on the CPU), which has GL_ARB_sparse_texture
# where the system's llvmpipe does not. For the sparse-texture path's tests (tests/CMakeLists.txt)
# and to try it by hand:
#   scripts/with-sparse-mesa.sh build/bin/orbis info
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
mesa="${ORBIS_SPARSE_MESA_DIR:-$root/.deps/sparse-mesa}"
if [ ! -f "$mesa/packages" ]; then
  echo "with-sparse-mesa: no Mesa unpacked in $mesa: run scripts/install-sparse-mesa.sh (scripts/install-deps.sh does)" >&2
  exit 1
fi
for lib in "$mesa"/usr/lib/*-linux-gnu; do
  export LD_LIBRARY_PATH="$lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
done
export VK_ICD_FILENAMES="$mesa/usr/share/vulkan/icd.d/lvp_icd.json"
# zink rather than llvmpipe; "software" lets it take lavapipe, a CPU device, which it passes over
# otherwise.
export GALLIUM_DRIVER=zink LIBGL_ALWAYS_SOFTWARE=1
exec "$@"
