#!/bin/sh
# Installs Orbis's build and run-time dependencies from Debian's archive, only those missing, and
# unpacks the newer Mesa the sparse-texture tests run on (scripts/install-sparse-mesa.sh). Needs
# root (or sudo) the first time; a second run with everything present installs nothing.
set -eu

packages="
  build-essential cmake ninja-build ccache pkg-config
  libglm-dev libgeographiclib-dev catch2 libbenchmark-dev
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libosmesa6-dev
  libstb-dev libtinygltf-dev nlohmann-json3-dev
  libglfw3-dev xvfb xauth
  xplanet-images fonts-dejavu-core libfontconfig-dev
  clang-14 libclang-rt-14-dev libvulkan1
  libturbojpeg0-dev libspng-dev libwebp-dev libsqlite3-dev libcurl4-openssl-dev libgdal-dev zlib1g-dev
"

missing=""
for p in $packages; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done

if [ -z "$missing" ]; then
  echo "install-deps: all dependencies present"
else
  echo "install-deps: installing$missing"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  # shellcheck disable=SC2086
  $sudo apt-get install -y -qq --no-install-recommends $missing
fi

# The sparse-texture path's tests run on a newer Mesa, unpacked in the checkout (not installed).
# Without the network the build goes on; those tests then fail, saying what is missing.
"$(dirname "$0")/install-sparse-mesa.sh" ||
  echo "install-deps: warning: the sparse-texture tests' Mesa could not be fetched; ctest -L sparse fails until scripts/install-sparse-mesa.sh succeeds" >&2
