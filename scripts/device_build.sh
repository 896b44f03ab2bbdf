#!/usr/bin/env bash
# Builds and tests pb4u on the GPU machine against PyTorch's LibTorch (CUDA), with the .debs that
# scripts/device_bundle.sh downloaded (device_bundle/debs/) unpacked into a prefix, never into /.
# See docs/cuda.md.
#
#   scripts/device_build.sh [--torch DIR] [--build-dir DIR] [--configure-only] [--no-tests]
#                           [--jobs N] [--logs DIR] [-- ctest arguments]
#
#   --torch DIR       Torch's CMake prefix (default: python3's torch.utils.cmake_prefix_path);
#                     --torch /usr uses Debian's LibTorch 1.13, which is how the unpacking and
#                     configuring are checked on a machine without a GPU
#   --build-dir DIR   default build-cuda
#   --configure-only  unpack, rewrite and configure, then stop
#   --no-tests        build but do not run ctest
#   --jobs N          build and ctest jobs (default: all cores)
#   --logs DIR        copy the configure, build and test logs there
# TORCH_CUDA_ARCH_LIST, when set, wins over the GPU's compute capability (nvidia-smi; else 9.0).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

torch_cmake="" build=build-cuda configure_only=0 tests=1 jobs=$(nproc) logs="" ctest_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --torch) torch_cmake=$2; shift ;;
    --build-dir) build=$2; shift ;;
    --configure-only) configure_only=1 ;;
    --no-tests) tests=0 ;;
    --jobs) jobs=$2; shift ;;
    --logs) logs=$2; shift ;;
    --) shift; ctest_args=("$@"); break ;;
    -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "device_build: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
say() { echo "device_build: $*"; }
die() { echo "device_build: $*" >&2; exit 1; }

bundle=$root/device_bundle
prefix=$bundle/prefix
shopt -s nullglob
debs=("$bundle"/debs/*.deb)
[ ${#debs[@]} -gt 0 ] || die "no .debs in $bundle/debs: run scripts/device_bundle.sh on a Debian 12 machine and carry device_bundle"

# Torch's CMake looks for nvcc on the PATH.
if ! command -v nvcc >/dev/null && [ -x /usr/local/cuda/bin/nvcc ]; then export PATH=/usr/local/cuda/bin:$PATH; fi
# The machine, as the first lines of the log (the image can change from one run to the next).
say "$(uname -m), $(. /etc/os-release && echo "$PRETTY_NAME"), $(c++ --version | head -n1), $(cmake --version | head -n1)"
command -v nvidia-smi >/dev/null && say "GPU: $(nvidia-smi --query-gpu=name,compute_cap,driver_version --format=csv,noheader | head -n1)"
command -v nvcc >/dev/null && say "nvcc: $(nvcc --version | tail -n1)"

# 1. Unpack every .deb into the prefix (dpkg -x: files only, no maintainer scripts, no dpkg database).
rm -rf "$prefix"
mkdir -p "$prefix"
for deb in "${debs[@]}"; do dpkg -x "$deb" "$prefix"; done
multiarch=$(c++ -print-multiarch 2>/dev/null || true)
libdir=$prefix/usr/lib/${multiarch:-x86_64-linux-gnu}
say "unpacked ${#debs[@]} packages into $prefix"

# 2. The packages' CMake files name their install prefix absolutely (/usr/lib/<arch>/libdraco.so.7,
# _IMPORT_PREFIX "/usr", ...): point every such path that the prefix holds into the prefix. Paths
# the prefix lacks (assimp's /usr/lib/<arch>/libz.so, librt.a) are the machine's own and stay.
rewritten=0
while IFS= read -r -d '' file; do
  changed=0
  for path in $(grep -o '/usr[^";:)> ]*' "$file" | sort -u || true); do
    [ -e "$prefix$path" ] || continue
    path_re=$(printf '%s' "$path" | sed 's/[].+*?^$(){}|\\[]/\\&/g')
    sed -i -E "s#([\"; :])$path_re([\";:)> ]|$)#\\1$prefix$path\\2#g" "$file"
    changed=1
  done
  rewritten=$((rewritten + changed))
done < <(find "$prefix" \( -name '*[Cc]onfig.cmake' -o -name '*[Tt]argets*.cmake' \) -print0)
say "pointed $rewritten CMake package files into the prefix"

# 3. Torch: its CMake prefix, include and lib directories.
if [ -z "$torch_cmake" ]; then
  torch_cmake=$(python3 -c 'import torch; print(torch.utils.cmake_prefix_path)') ||
    die "no PyTorch in python3: give --torch <Torch's CMake prefix>"
fi
case "$torch_cmake" in
  */share/cmake) torch_root=$(cd "$torch_cmake/../.." && pwd) ;;  # a PyTorch wheel's torch/
  *) torch_root=$torch_cmake ;;
esac
say "Torch: $torch_cmake"

# 4. A wheel's torch/include ships its own fmt (12 in 2.11), which shadows the system's and breaks
# spdlog (built against fmt 9): put a copy of the fmt that spdlog comes with ahead of it. Only
# fmt/ is copied: -I/usr/include itself would reorder the system headers.
cxx_flags=""
if [ -d "$torch_root/include/fmt" ] && [ "$torch_root/include" != /usr/include ]; then
  fmt_src=/usr/include/fmt
  [ -d "$prefix/usr/include/spdlog" ] && [ -d "$prefix/usr/include/fmt" ] && fmt_src=$prefix/usr/include/fmt
  [ -d "$fmt_src" ] || die "Torch ships fmt headers but there is no $fmt_src for spdlog"
  rm -rf "$bundle/fmt-include"
  mkdir -p "$bundle/fmt-include"
  cp -r "$fmt_src" "$bundle/fmt-include/fmt"
  cxx_flags="-I$bundle/fmt-include"
  say "fmt for spdlog: $fmt_src (ahead of $torch_root/include/fmt)"
fi

# 5. libassimp.so needs libdraco/libminizip from the prefix at link time (-lminizip, rpath-link).
link_flags="-L$libdir -Wl,-rpath-link,$libdir"
arch=${TORCH_CUDA_ARCH_LIST:-}
if [ -z "$arch" ] && command -v nvidia-smi >/dev/null; then
  arch=$(nvidia-smi --query-gpu=compute_cap --format=csv,noheader 2>/dev/null | head -n1 | tr -d ' ') || arch=""
fi
arch=${arch:-9.0}  # Torch reads TORCH_CUDA_ARCH_LIST, not CMAKE_CUDA_ARCHITECTURES
gloo=ON
compgen -G "$bundle/debs/libgloo-dev_*.deb" >/dev/null || gloo=OFF

generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
mkdir -p "$build"
save_logs() {
  [ -n "$logs" ] || return 0
  mkdir -p "$logs"
  for f in "$build/device_configure.log" "$build/device_build.log" "$build/device_ctest.log"; do
    [ -f "$f" ] && cp "$f" "$logs/"
  done
  return 0
}
trap save_logs EXIT
say "configuring $build (TORCH_CUDA_ARCH_LIST=$arch, PB4U_GLOO=$gloo)"
if ! cmake -S . -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix/usr;$torch_cmake" \
    -DCMAKE_CXX_FLAGS="$cxx_flags" \
    -DCMAKE_EXE_LINKER_FLAGS="$link_flags" -DCMAKE_SHARED_LINKER_FLAGS="$link_flags" \
    -DTORCH_CUDA_ARCH_LIST="$arch" -DPB4U_GLOO="$gloo" >"$build/device_configure.log" 2>&1; then
  tail -n 40 "$build/device_configure.log" >&2
  die "configure failed (log: $build/device_configure.log)"
fi
# What the configure found, where a reader checks that the prefix was used.
grep -E '^(Torch_DIR|assimp_DIR|draco_DIR|CGAL_INCLUDE_DIR|NANOFLANN_INCLUDE_DIR|GLOO_INCLUDE_DIR|GMP_LIBRARY|MPFR_LIBRARY|spdlog_DIR|yaml-cpp_DIR|HDF5_CXX_LIBRARY_hdf5_cpp):' \
  "$build/CMakeCache.txt" | sed 's/^/device_build:   /' || true
[ "$configure_only" = 1 ] && { say "configured (--configure-only)"; exit 0; }

start=$(date +%s)
if ! cmake --build "$build" -j "$jobs" >"$build/device_build.log" 2>&1; then
  grep -E 'error|Error|FAILED' "$build/device_build.log" | head -n 40 >&2
  die "build failed (log: $build/device_build.log)"
fi
say "built in $(($(date +%s) - start)) s"
[ "$tests" = 1 ] || exit 0

# The test binaries and pb4u (run by the CLI tests) find libtorch and the prefix's libraries.
export LD_LIBRARY_PATH="$torch_root/lib:$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
status=0
ctest --test-dir "$build" -j "$jobs" --timeout 900 --output-on-failure "${ctest_args[@]}" \
  >"$build/device_ctest.log" 2>&1 || status=$?
grep -E 'tests passed|tests failed|Total Test time|[0-9]+ - .*\((Failed|SEGFAULT|Timeout|Subprocess aborted|Skipped|Not Run|Exception)\)' \
  "$build/device_ctest.log" | tail -n 60
say "the cuda label ($(ctest --test-dir "$build" -L cuda -N | tail -n 1 | tr -d '\n')):"
grep -E '^ *[0-9]+/[0-9]+ Test +#[0-9]+: Cuda[A-Za-z]*\.' "$build/device_ctest.log" || true
exit $status
