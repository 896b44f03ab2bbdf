#!/usr/bin/env bash
# Whether a method keeps the cloth free of the body on every frame of every scene in
# configs/scenes (the long version of the per-frame checks ctest runs on small scenes): each
# scene with a body rolled out by the intersection-free solver (default), the penalty solver, a
# network, or a network refined by the solver, then one row per scene from its energies.csv:
# frames with a vertex inside the body, frames with a cloth edge through a body triangle (an edge
# can cut a limb with both ends outside), the most of each on one frame, the frames that left
# cloth out of barrier contact, and the positive energy. Writes DIR/report.md and prints it.
#
# Usage: scripts/intersection_free_report.sh [--out DIR] [--frames N] [--threads N]
#            [--method barrier|penalty|net] [--checkpoint FILE] [--refine N]
#            [--set KEY=VALUE ...] [SCENE ...]
#   SCENE          scene files (default: every configs/scenes/*.yaml with a body)
#   --method       barrier (default): simulate --method reference with solver.contact barrier;
#                  penalty: simulate --method penalty; net: the network in --checkpoint
#   --checkpoint   model file for --method net (default data/pretrained/pb4u.h5)
#   --refine N     with --method net: each step refined by N iterations of the barrier solver
#   --frames N     frames per scene (default 30)
#   --set KEY=VAL  passed to simulate after the method's own settings (repeatable), e.g.
#                  --set physics.solver.barrier_keeps_penalty=true
# Scenes need the quick dataset (data/generated/quick, scripts/demo.sh makes it).
set -euo pipefail
cd "$(dirname "$0")/.."
out=runs/intersection_free frames=30 threads=1 method=barrier checkpoint=data/pretrained/pb4u.h5 refine=0 scenes=() sets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=$2; shift ;;
    --frames) frames=$2; shift ;;
    --threads) threads=$2; shift ;;
    --method) method=$2; shift ;;
    --checkpoint) checkpoint=$2; shift ;;
    --refine) refine=$2; shift ;;
    --set) sets+=(--set "$2"); shift ;;
    -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;;
    -*) echo "intersection_free_report.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) scenes+=("$1") ;;
  esac
  shift
done
case "$method" in
  barrier) args=(--method reference --set physics.solver.contact=barrier) ;;
  penalty) args=(--method penalty) ;;
  net) args=(--checkpoint "$checkpoint" --set physics.solver.contact=barrier)
       [ "$refine" -gt 0 ] && args+=(--refine "$refine") ;;
  *) echo "intersection_free_report.sh: --method: '$method' is not barrier, penalty or net" >&2; exit 2 ;;
esac
if [ ${#scenes[@]} -eq 0 ]; then
  for s in configs/scenes/*.yaml; do
    grep -q '^body:' "$s" && grep -A3 '^body:' "$s" | grep -q 'dataset:' && scenes+=("$s")
  done
fi
PB4U=${PB4U_BUILD_DIR:-build}/pb4u
[ -x "$PB4U" ] || { echo "intersection_free_report.sh: $PB4U not built (scripts/build.sh)" >&2; exit 1; }
PY=/usr/bin/python3
[ -x "$PY" ] || PY=$(command -v python3)
mkdir -p "$out"
label="$method"
[ "$method" = net ] && label="net $(basename "$checkpoint")" && [ "$refine" -gt 0 ] && label="$label + $refine it"
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .yaml)
  echo "== $name ($label, $frames frames)"
  "$PB4U" --threads "$threads" simulate --scene "$scene" --frames "$frames" "${args[@]}" \
    --set outputs.mesh_format=none --set outputs.plot=false --set outputs.preview=false \
    --set outputs.usd=false ${sets[@]+"${sets[@]}"} --out "$out/$name" 2>&1 | tail -1
done
"$PY" - "$out" "$label" "$frames" "${scenes[@]}" <<'EOF'
import csv, os, sys
out, label, frames, scenes = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
lines = [f"# Free of the body? {label}, {frames} frames a scene", "",
         "| scene | frames | with a vertex inside (most, deepest mm) | with an edge through (most) "
         "| out of barrier contact (most vertices) | positive energy mean J |",
         "|---|---|---|---|---|---|"]
for scene in scenes:
    name = os.path.splitext(os.path.basename(scene))[0]
    path = os.path.join(out, name, "energies.csv")
    if not os.path.exists(path):
        lines.append(f"| {name} | no energies.csv | | | | |")
        continue
    rows = [r for r in csv.DictReader(open(path)) if r["total"] != "nan"]
    def col(key):
        return [float(r[key]) for r in rows] if rows and key in rows[0] else []
    inside, deep, through = col("penetrating_fraction"), col("max_penetration_mm"), col("edges_through_body")
    excluded = col("contact_excluded")
    positive = [sum(float(r[k]) for k in ("stretch", "bending", "collision") if k in r) for r in rows]
    n = len(rows)
    cell = lambda v, most: f"{sum(x > 0 for x in v)} ({most})" if v else "-"
    lines.append(
        f"| {name} | {n} | {cell(inside, f'{100 * max(inside):.2f}%, {max(deep):.1f} mm' if inside else '')} "
        f"| {cell(through, int(max(through)) if through else '')} "
        f"| {cell(excluded, int(max(excluded)) if excluded else '')} "
        f"| {sum(positive) / n if n else float('nan'):.4g} |")
text = "\n".join(lines) + "\n"
open(os.path.join(out, "report.md"), "w").write(text)
print(text)
EOF
