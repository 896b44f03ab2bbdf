#!/usr/bin/env bash
# Downloads, on this (Debian 12) machine, the .debs that the GPU machine lacks for building pb4u
# against PyTorch's LibTorch, into device_bundle/debs/ (ignored by git). scripts/device_build.sh
# unpacks them there into a prefix. See docs/cuda.md.
#
#   scripts/device_bundle.sh [--no-cgal] [--no-gloo] [--with-present] [--out DIR]
#
# Default set: what docs/cuda.md lists as missing on the GPU machine's image (assimp with its
# draco and minizip, nanoflann, Gloo's headers, CGAL with GMP/MPFR).
#   --no-cgal       leave out CGAL/GMP/MPFR (only for an image that has them: pb4u's remeshing
#                   needs them at configure time)
#   --no-gloo       leave out Gloo's headers (pb4u then builds without data-parallel training)
#   --with-present  also the packages the image already had (HDF5, spdlog/fmt, yaml-cpp, CLI11,
#                   Eigen, GoogleTest, Boost headers), for an image that loses them
# Carry device_bundle/debs to the GPU machine. The whole working tree travels with it, so the two
# together must stay under the device tool's 64 MiB: the script prints both and fails above it.
set -euo pipefail
cd "$(dirname "$0")/.."

out=device_bundle
cgal=1 gloo=1 present=0
while [ $# -gt 0 ]; do
  case "$1" in
    --no-cgal) cgal=0 ;;
    --no-gloo) gloo=0 ;;
    --with-present) present=1 ;;
    --out) out=$2; shift ;;
    -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "device_bundle: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done

# Missing on the GPU image: runtime libraries and their -dev halves (headers, CMake packages).
packages=(libassimp5 libassimp-dev libdraco7 libdraco-dev libminizip1 libminizip-dev libnanoflann-dev)
# Headers only: libtorch carries Gloo's code, the wheel lacks its headers.
[ "$gloo" = 1 ] && packages+=(libgloo-dev)
[ "$cgal" = 1 ] && packages+=(libcgal-dev libgmp-dev libgmp10 libgmpxx4ldbl libmpfr-dev libmpfr6)
if [ "$present" = 1 ]; then
  packages+=(
    libhdf5-dev libhdf5-103-1 libhdf5-cpp-103-1 libhdf5-hl-100 libhdf5-hl-cpp-100 libsz2 libaec0 libaec-dev
    hdf5-helpers
    libspdlog-dev libspdlog1.10 libfmt-dev libfmt9
    libyaml-cpp-dev libyaml-cpp0.7
    libcli11-dev libeigen3-dev libgtest-dev
    libboost1.74-dev
  )
fi

if ! grep -q 'VERSION_CODENAME=bookworm' /etc/os-release 2>/dev/null; then
  echo "device_bundle: warning: this is not Debian 12 (bookworm); the GPU machine was checked with bookworm's .debs" >&2
fi

debs="$out/debs"
# A fresh set; prefix/ and fmt-include/ are what device_build.sh made of the last one.
rm -rf "$debs" "$out/prefix" "$out/fmt-include"
mkdir -p "$debs"
# apt-get download fetches exactly the named packages (no dependencies), as the apt lists
# name them: a 404 means the lists are stale (apt-get update).
sandbox=()
[ "$(id -u)" = 0 ] && sandbox=(-o APT::Sandbox::User=root)  # root downloads into a root-owned folder
if ! (cd "$debs" && apt-get download -q "${sandbox[@]}" "${packages[@]}" >/dev/null); then
  echo "device_bundle: apt-get download failed (stale lists? run apt-get update)" >&2
  exit 1
fi
(cd "$debs" && for f in *.deb; do dpkg-deb --show --showformat='${Package} ${Version}\n' "$f"; done) >"$out/MANIFEST"
echo "gloo=$gloo cgal=$cgal present=$present" >>"$out/MANIFEST"

limit=$((64 * 1024 * 1024))
bundle=$(du -sb "$debs" | cut -f1)
tree=$(git ls-files -z --cached --others --exclude-standard | xargs -0 du -cb 2>/dev/null | tail -n1 | cut -f1)
echo "device_bundle: ${#packages[@]} packages in $debs: $((bundle / 1024)) KiB; working tree $((tree / 1024)) KiB; together $(((bundle + tree) / 1024)) KiB of $((limit / 1024)) KiB"
if [ $((bundle + tree)) -gt "$limit" ]; then
  echo "device_bundle: over the device tool's 64 MiB carry limit" >&2
  exit 1
fi
