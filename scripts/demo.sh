#!/usr/bin/env bash
# One command from a fresh clone: install what is missing, build, and run the main job on a
# small built-in default. Outputs go to demo_out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
PB4U=${PB4U_BUILD_DIR:-build}/pb4u
OUT=demo_out
mkdir -p "$OUT"

echo "== pb4u inspect data/meshes/tshirt.obj (the shipped t-shirt)"
"$PB4U" inspect data/meshes/tshirt.obj | tee "$OUT/tshirt_inspect.txt"
echo
echo "Outputs are in $OUT/."
