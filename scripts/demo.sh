#!/usr/bin/env bash
# One command from a fresh clone: install what is missing, build, generate the quick dataset,
# simulate a scene with a Pb4U model, and evaluate Pb4U vs MGN on the quick levels.
# Outputs go to demo_out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
PB4U=${PB4U_BUILD_DIR:-build}/pb4u
OUT=demo_out
mkdir -p "$OUT"

echo "== pb4u inspect data/meshes/tshirt.obj (the shipped t-shirt)"
"$PB4U" inspect data/meshes/tshirt.obj | tee "$OUT/tshirt_inspect.txt"

DATA=data/generated/quick/quick.h5
# Generated again when its config changed since (a dataset of an older config would be reused).
if [ ! -f "$DATA" ] || [ configs/data/quick.yaml -nt "$DATA" ]; then
  echo "== pb4u generate (quick CPU-scale dataset, about two minutes)"
  "$PB4U" generate --config configs/data/quick.yaml --out data/generated/quick
fi

PB4U_MODEL=data/pretrained/pb4u.h5
MGN_MODEL=data/pretrained/mgn.h5
if [ ! -f "$PB4U_MODEL" ] || [ ! -f "$MGN_MODEL" ]; then
  echo "== No shipped models in data/pretrained/: training SHORT demo models instead"
  echo "   (configs/train/demo.yaml, 400 steps each, a few minutes; far from converged)."
  for kind in pb4u mgn; do
    if [ ! -f "runs/demo_$kind/final.pt" ]; then
      rm -rf "runs/demo_$kind"
      scaling=on
      [ "$kind" = mgn ] && scaling=off  # the paper's MGN: fixed depth, no update scaling
      "$PB4U" train --config configs/train/demo.yaml --set model.kind=$kind \
        --set model.update_scaling=$scaling --out "runs/demo_$kind"
    fi
    "$PB4U" export --checkpoint "runs/demo_$kind/final.pt" --out "$OUT/demo_$kind.h5"
  done
  PB4U_MODEL=$OUT/demo_pb4u.h5
  MGN_MODEL=$OUT/demo_mgn.h5
fi

echo "== pb4u inspect $PB4U_MODEL"
"$PB4U" inspect "$PB4U_MODEL" | tee "$OUT/model_inspect.txt"

echo "== pb4u simulate: t-shirt on the walking CMU mannequin, 60 frames"
"$PB4U" simulate --checkpoint "$PB4U_MODEL" --scene configs/scenes/tshirt_walk.yaml --out "$OUT/tshirt_walk"

echo "== pb4u evaluate: Pb4U vs MGN on the quick levels (Table 1 layout)"
"$PB4U" evaluate --checkpoint "$PB4U_MODEL" --checkpoint "$MGN_MODEL" \
  --config configs/eval/quick.yaml | tee "$OUT/table1.txt"

echo
echo "Outputs are in $OUT/:"
echo "  tshirt_walk/   garment_*.obj, body_*.obj, garment.pc2 + body.pc2 (Blender: Mesh Cache"
echo "                 modifier on garment_0000.obj), rollout.h5, energies.csv, energies.png,"
echo "                 preview.png (front and side views; red = inside the body)"
echo "  table1.txt     Table-1-style metrics (--format json for SPEC 7's JSON)"
