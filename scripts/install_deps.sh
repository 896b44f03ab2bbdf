#!/usr/bin/env bash
# Installs the Debian packages pb4u builds and runs with, if any is missing.
# Quiet when everything is there. Needs root (apt-get); otherwise prints the command.
#   scripts/install_deps.sh            what pb4u builds and runs with
#   scripts/install_deps.sh --blender  also Blender (~300 MB), for bench's Blender rows and the
#                                      add-on's test (scripts/blender/pb4u_addon)
#   scripts/install_deps.sh --tinyusdz also node and the npm package tinyusdz (~3 MB, into
#                                      ~/.cache/pb4u/node), the independent USD reader of the tests
set -euo pipefail

PACKAGES=(
  cmake ninja-build g++ pkg-config ccache
  libtorch-dev libeigen3-dev libhdf5-dev libassimp-dev libcli11-dev libspdlog-dev
  libyaml-cpp-dev libgtest-dev libnanoflann-dev nlohmann-json3-dev
  # Headers of Gloo, the transport of libtorch's c10d ProcessGroupGloo (data-parallel training).
  libgloo-dev
  # Isotropic remeshing of bodies and garments to a target triangle count (header-only; GMP/MPFR kernel).
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  # libtorch links libblas.so.3; without this it resolves to the reference BLAS (19x slower).
  libopenblas0-openmp
  # Plots and previews: pb4u runs them under the first python3 on PATH that imports matplotlib.
  python3-matplotlib
)
for arg in "$@"; do
  case $arg in
    --blender) PACKAGES+=(blender) ;;
    --tinyusdz)  # Debian's nodejs and npm, unless a node and npm are already on PATH
      command -v node >/dev/null || PACKAGES+=(nodejs)
      command -v npm >/dev/null || PACKAGES+=(npm)
      TINYUSDZ=1 ;;
    *) echo "usage: scripts/install_deps.sh [--blender] [--tinyusdz]" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "pb4u: missing packages: ${missing[*]}" >&2
    echo "pb4u: run as root, or: sudo apt-get install -y ${missing[*]}" >&2
    exit 1
  fi
  echo "pb4u: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# TinyUSDZ's WebAssembly build, where tests/io/usd_tinyusdz_test.cpp looks for it.
if [ "${TINYUSDZ:-0}" = 1 ] && [ ! -f "$HOME/.cache/pb4u/node/node_modules/tinyusdz/tinyusdz.wasm" ]; then
  echo "pb4u: installing the npm package tinyusdz into $HOME/.cache/pb4u/node"
  npm install --silent --no-audit --no-fund --prefix "$HOME/.cache/pb4u/node" tinyusdz@0.9.0-rc10
fi

# libblas.so.3 must be OpenBLAS, not the reference implementation.
alt=libblas.so.3-$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)
current=$(update-alternatives --query "$alt" 2>/dev/null | awk '/^Value:/ {print $2}')
if [ -n "$current" ] && [[ "$current" != *openblas* ]]; then
  if [ "$(id -u)" -eq 0 ]; then
    best=$(update-alternatives --list "$alt" | grep openblas-openmp | head -n1)
    [ -n "$best" ] && update-alternatives --quiet --set "$alt" "$best"
    echo "pb4u: libblas.so.3 now points to $best"
  else
    echo "pb4u: warning: libblas.so.3 is the slow reference BLAS ($current); as root run:" >&2
    echo "  update-alternatives --config $alt" >&2
  fi
fi
