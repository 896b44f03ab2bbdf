#!/usr/bin/env bash
# Runs each libFuzzer target for a bounded time and reports executions and crashes.
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET=60] [TARGET...]
# Builds in build-fuzz/ with clang (ASan + coverage). Crashing inputs land in
# build-fuzz/findings/<target>/; the summary is printed and written to build-fuzz/fuzz_summary.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET=${1:-60}
shift || true
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=(mesh_fuzz config_fuzz checkpoint_fuzz bvh_fuzz)
scripts/install_deps.sh
command -v clang++ >/dev/null || { echo "pb4u: fuzzing needs clang (apt-get install clang)" >&2; exit 1; }
B=build-fuzz
if [ ! -f $B/CMakeCache.txt ]; then
  CC=clang CXX=clang++ cmake -S . -B $B -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DPB4U_FUZZ=ON -DPB4U_BUILD_TESTS=OFF -DPB4U_USE_PCH=OFF >/dev/null
fi
ninja -C $B "${TARGETS[@]}" >/dev/null

# Seed corpora: small valid inputs of each kind.
seed() { mkdir -p "$B/corpus/$1"; }
seed mesh_fuzz; seed config_fuzz; seed checkpoint_fuzz; seed bvh_fuzz
printf '\x00v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n' >$B/corpus/mesh_fuzz/quad_obj
printf '\x01ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >$B/corpus/mesh_fuzz/tri_ply
printf '\x02solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' >$B/corpus/mesh_fuzz/tri_stl
printf 'material:\n  density: 0.2\n  mu: 23600\nranges:\n  mu: [1, 2]\nsteps: 3\nflag: true\nkind: b\nlevels: [1, 2]\n' >$B/corpus/config_fuzz/full_yaml
printf 'HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n  JOINT Chest\n  {\n    OFFSET 0 10 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    End Site\n    {\n      OFFSET 0 5 0\n    }\n  }\n}\nMOTION\nFrames: 2\nFrame Time: 0.0083333\n0 90 0 0 0 0 10 0 0\n1 90 0 5 0 0 20 0 0\n' >$B/corpus/bvh_fuzz/two_joints_bvh
PB4U_FUZZ_SEED_DIR=$B/corpus/checkpoint_fuzz $B/tests/fuzz/checkpoint_fuzz -runs=0 >/dev/null 2>&1 || true

export ASAN_OPTIONS=detect_leaks=0:alloc_dealloc_mismatch=0:detect_odr_violation=0
summary=$B/fuzz_summary.txt
: >"$summary"
for t in "${TARGETS[@]}"; do
  mkdir -p "$B/findings/$t"
  log=$B/$t.log
  set +e
  $B/tests/fuzz/$t "$B/corpus/$t" -max_total_time="$SECONDS_PER_TARGET" -max_len=65536 \
    -rss_limit_mb=4096 -timeout=10 -artifact_prefix="$B/findings/$t/" -print_final_stats=1 >"$log" 2>&1
  rc=$?
  set -e
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  crashes=$(find "$B/findings/$t" -type f | wc -l)
  line="$t: ${execs:-0} executions in ${SECONDS_PER_TARGET}s, exit $rc, crash files: $crashes"
  echo "$line" | tee -a "$summary"
done
