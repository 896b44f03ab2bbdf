#!/usr/bin/env bash
# The smallest reproduction of the finest-level gap: the square cloth of
# configs/scenes/hanging_cloth.yaml (0.6 m, pinned along its top row, gravity only) at several
# resolutions, each network against the reference solver on the same scene. The network
# calibrated on ~2.7 cm edges meets 3 cm edges at 21 vertices per side and 1 cm edges (Lv.5's)
# at 61. Minutes, not hours: the loop to iterate on fine-level behaviour with. Writes
# DIR/report.md (and prints it): per resolution the solver's positive energy (stretch +
# bending, J per frame, mean over frames) and each network's, with its ratio to the solver's.
#
# Usage: scripts/hanging_resolution.sh [--out DIR] [--frames N] [--resolutions "21 41 61"]
#            [--threads N] [--fresh] [CHECKPOINT ...]
#   CHECKPOINT     networks (default data/pretrained/pb4u.h5)
#   --frames N     frames per rollout (default 90: every network reaches its plateau by 30)
#   --fresh        run the solver again even if DIR holds its run at that resolution and length
# The solver's rollouts stay in DIR/reference_<res>_<frames>/ and are reused.
set -euo pipefail
cd "$(dirname "$0")/.."
out=runs/hanging_resolution frames=90 resolutions="21 41 61" threads=1 fresh=0 models=()
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=$2; shift ;;
    --frames) frames=$2; shift ;;
    --resolutions) resolutions=$2; shift ;;
    --threads) threads=$2; shift ;;
    --fresh) fresh=1 ;;
    -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;;
    -*) echo "hanging_resolution.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) models+=("$1") ;;
  esac
  shift
done
[ ${#models[@]} -gt 0 ] || models=(data/pretrained/pb4u.h5)
for m in "${models[@]}"; do [ -f "$m" ] || { echo "hanging_resolution.sh: $m: no such model file" >&2; exit 2; }; done
pb4u=build/pb4u
[ -x $pb4u ] || { echo "hanging_resolution.sh: build first (scripts/build.sh): $pb4u is missing" >&2; exit 2; }
scene=configs/scenes/hanging_cloth.yaml
mkdir -p "$out"

# mean positive energy (stretch + bending) per frame of a rollout's energies.csv
positive_mean() {
  awk -F, 'NR > 1 && $2 != "nan" { s += $2 + $3; n++ } END { if (n) printf "%.4g", s / n; else print "nan" }' "$1/energies.csv"
}
roll() {  # roll DIR METHOD RES [CHECKPOINT]
  local dir=$1 method=$2 res=$3 ckpt=${4:-}
  "$pb4u" --threads "$threads" simulate --scene $scene --method "$method" ${ckpt:+--checkpoint "$ckpt"} \
    --out "$dir" --frames "$frames" --format none --preview off --set garment.resolution="$res" > "$dir.log" 2>&1 ||
    { echo "hanging_resolution.sh: $method at resolution $res failed, see $dir.log" >&2; exit 1; }
}

report="$out/report.md"
{
  printf '| vertices per side | grid spacing mm | solver E+ J |'
  for m in "${models[@]}"; do printf ' %s E+ J (x solver) |' "$(basename "$m")"; done
  printf '\n|---|---|---|'
  for m in "${models[@]}"; do printf -- '---|'; done
  printf '\n'
} > "$report"
for res in $resolutions; do
  ref="$out/reference_${res}_${frames}"
  if [ $fresh = 1 ] || [ ! -f "$ref/energies.csv" ]; then
    echo "solver, $res vertices per side, $frames frames ..." >&2
    rm -rf "$ref"; roll "$ref" reference "$res"
  fi
  e_ref=$(positive_mean "$ref")
  edge_mm=$(awk -v r="$res" 'BEGIN { printf "%.1f", 600 / (r - 1) }')
  row="| $res | $edge_mm | $e_ref |"
  for i in "${!models[@]}"; do
    dir="$out/net${i}_${res}_${frames}"
    echo "$(basename "${models[$i]}"), $res vertices per side ..." >&2
    rm -rf "$dir"; roll "$dir" net "$res" "${models[$i]}"
    e=$(positive_mean "$dir")
    row+=" $e ($(awk -v a="$e" -v b="$e_ref" 'BEGIN { printf "%.1f", a / b }')x) |"
  done
  echo "$row" >> "$report"
done
cat "$report"
