#!/bin/sh
# Unpacks a newer Mesa from Debian's bookworm-backports into .deps/sparse-mesa, beside the system's,
# for the tests of the sparse-texture path (GL_ARB_sparse_texture): the system's Mesa 22.3 lacks the
# extension, and Mesa 25's zink driver over lavapipe (Vulkan on the CPU) has it. Nothing is
# installed system-wide: the tests that need it run with tests/sparse-mesa-env.sh's variables, and
# everything else keeps the system's llvmpipe. The packages come through apt, checked against
# Debian's archive key; a second run with them unpacked does nothing.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
target="${ORBIS_SPARSE_MESA_DIR:-$root/.deps/sparse-mesa}"
packages="mesa-libgallium libegl-mesa0 libgbm1 mesa-vulkan-drivers libdrm2 libdrm-amdgpu1 libdrm-intel1"

if [ -f "$target/packages" ]; then
  echo "install-sparse-mesa: $(head -n 1 "$target/packages") present in $target"
  exit 0
fi
. /etc/os-release
if [ "${VERSION_CODENAME:-}" != bookworm ]; then
  echo "install-sparse-mesa: needs Debian 12 (bookworm) for its backports, this is ${PRETTY_NAME:-unknown}" >&2
  exit 1
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/lists/partial" "$work/cache/archives/partial" "$work/debs"
echo "deb [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian bookworm-backports main" \
  > "$work/sources.list"
# apt with a list and cache of its own: the system's sources and state stay as they are.
apt_private="-o Dir::Etc::SourceList=$work/sources.list -o Dir::Etc::SourceParts=/dev/null
  -o Dir::State::Lists=$work/lists -o Dir::Cache=$work/cache -o Debug::NoLocking=1
  -o APT::Sandbox::User=$(id -un) -qq"
echo "install-sparse-mesa: fetching $packages from bookworm-backports"
# shellcheck disable=SC2086
apt-get $apt_private update
cd "$work/debs"
for p in $packages; do
  # shellcheck disable=SC2086
  apt-get $apt_private download "$p/bookworm-backports"
done

rm -rf "$target.partial"
mkdir -p "$target.partial"
for deb in "$work"/debs/*.deb; do
  dpkg-deb -x "$deb" "$target.partial"
done
echo "Mesa $(dpkg-deb -f "$work"/debs/mesa-libgallium_*.deb Version) (bookworm-backports)" > "$target.partial/packages"
ls "$work/debs" >> "$target.partial/packages"
rm -rf "$target"
mv "$target.partial" "$target"
echo "install-sparse-mesa: $(head -n 1 "$target/packages") unpacked in $target"
