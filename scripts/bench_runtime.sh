#!/usr/bin/env bash
# Before/after of each runtime setting pb4u applies at start-up (docs/performance.md):
# OpenMP wait policy and spin, allocator tuning and thread count, on configs/bench/runtime.yaml.
# Usage: scripts/bench_runtime.sh [OUT_DIR=runs/bench/runtime]. Needs the quick dataset.
set -euo pipefail
cd "$(dirname "$0")/.."
PB4U=${PB4U_BUILD_DIR:-build}/pb4u
OUT=${1:-runs/bench/runtime}
mkdir -p "$OUT"
run() {  # NAME THREADS ENV...
  local name=$1 threads=$2
  shift 2
  env "$@" "$PB4U" -q --threads "$threads" bench --config configs/bench/runtime.yaml --out "$OUT/$name" >/dev/null
  awk -F, -v n="$name" 'NR > 1 { printf "| %s | %s | Lv.%s | %s | %s | %s |\n", n, $6, $1, $2, $4, $7 }' "$OUT/$name/bench.csv"
}
echo "| setting | threads | level | triangles | method | median ms/frame |"
echo "|---|---|---|---|---|---|"
run default-2threads 2
run passive-nospin-2threads 2 GOMP_SPINCOUNT=0
run omp-active-2threads 2 OMP_WAIT_POLICY=ACTIVE
run glibc-malloc-2threads 2 PB4U_DEFAULT_MALLOC=1
run default-1thread 1
run glibc-malloc-1thread 1 PB4U_DEFAULT_MALLOC=1
