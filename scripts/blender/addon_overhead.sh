#!/usr/bin/env bash
# What the Blender add-on adds to `pb4u simulate`'s own time (docs/blender.md): the headless
# scene of its test (tests/eval/blender_addon_scene.py: a skinned cylinder, a tube pinned at
# its top) run through the add-on's operator RUNS times (export + simulate + load, Blender's
# start-up left out), then the scene.yaml the add-on wrote run by plain `pb4u simulate` RUNS
# times; medians, with THREADS pb4u threads.
#   scripts/blender/addon_overhead.sh [--frames 60] [--segments 48] [--runs 5] [--threads 1]
set -euo pipefail
cd "$(dirname "$0")/../.."
FRAMES=60 SEGMENTS=48 RUNS=5 THREADS=1
while [ $# -gt 0 ]; do
  case $1 in
    --frames) FRAMES=$2; shift 2 ;;
    --segments) SEGMENTS=$2; shift 2 ;;
    --runs) RUNS=$2; shift 2 ;;
    --threads) THREADS=$2; shift 2 ;;
    *) echo "usage: scripts/blender/addon_overhead.sh [--frames N] [--segments N] [--runs N] [--threads N]" >&2; exit 2 ;;
  esac
done
PB4U=${PB4U:-build/pb4u}
command -v blender >/dev/null || { echo "addon_overhead: Blender is not installed (scripts/install_deps.sh --blender)" >&2; exit 1; }
[ -x "$PB4U" ] || { echo "addon_overhead: $PB4U not built (scripts/build.sh)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

blender -b --factory-startup --python tests/eval/blender_addon_scene.py -- --pb4u "$PB4U" --out "$out" \
  --frames "$FRAMES" --segments "$SEGMENTS" --threads "$THREADS" --runs "$RUNS" >"$out/blender.log" 2>&1 ||
  { tail -5 "$out/blender.log" >&2; exit 1; }
plain=()
for _ in $(seq "$RUNS"); do
  start=$(date +%s.%N)
  "$PB4U" -q --threads "$THREADS" simulate --checkpoint data/pretrained/pb4u.h5 --scene "$out/cache/scene.yaml" \
    --out "$out/plain" >/dev/null
  plain+=("$(echo "$(date +%s.%N) - $start" | bc)")
done
python3 - "$out/result.json" "$FRAMES" "$SEGMENTS" "$THREADS" "${plain[@]}" <<'EOF'
import json, statistics, sys
runs = json.load(open(sys.argv[1]))["runs"]
frames, segments, threads = sys.argv[2:5]
plain = [float(s) for s in sys.argv[5:]]
med = lambda key: statistics.median(r[key] for r in runs)
addon = statistics.median(r["export"] + r["simulate"] + r["load"] for r in runs)
base = statistics.median(plain)
print(f"scene: {frames} frames, body and garment of {segments} segments, {threads} pb4u thread(s), {len(runs)} runs each (medians)")
print(f"plain pb4u simulate:  {base:.3f} s")
print(f"add-on operator:      {addon:.3f} s (export {med('export'):.3f} s, simulate {med('simulate'):.3f} s, load {med('load'):.3f} s)")
print(f"overhead:             {100 * (addon / base - 1):+.1f}%")
EOF
