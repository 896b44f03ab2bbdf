#!/usr/bin/env bash
# Held-out stability report (issue 14, SPEC 9): the networks and the reference solver on the
# held-out evaluation, with a body (configs/eval/heldout.yaml) and pinned without one
# (configs/eval/heldout_pinned.yaml); a markdown table of each network against the solver on
# the same sequences (scripts/stability_table.py) to runs/stability/report.md and stdout.
#
# Usage: scripts/stability_report.sh [--quick] [--out DIR] [--split NAME] [--dataset FILE]
#                                    [--threads N] [--set KEY=VALUE ...] [CHECKPOINT ...]
#   CHECKPOINT    networks to evaluate (default data/pretrained/pb4u.h5 data/pretrained/mgn.h5)
#   --quick       a smoke test: level 1, the t-shirt, one motion, 5 frames (minutes, not hours)
#   --split NAME  motions of this split instead of "heldout" (e.g. test, for a dataset without it)
#   --dataset F   another generated dataset (default: the configs', data/generated/quick/quick.h5)
#   --threads N   torch threads for pb4u (default 1)
#   --set K=V     any evaluate-config override for both cases, e.g. --set levels=[1] (repeatable)
# The full run rolls the solver out for 300 frames per sequence: hours on a CPU. Each case's
# JSON is kept in DIR (body.json, pinned.json) and the report is rebuilt from them.
set -euo pipefail
cd "$(dirname "$0")/.."
out=runs/stability quick=0 split="" dataset="" threads=1 models=() extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --out) out=$2; shift ;;
    --split) split=$2; shift ;;
    --dataset) dataset=$2; shift ;;
    --threads) threads=$2; shift ;;
    --set) extra+=(--set "$2"); shift ;;
    -h|--help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "stability_report.sh: unknown option $1" >&2; exit 2 ;;
    *) models+=("$1") ;;
  esac
  shift
done
[ ${#models[@]} -gt 0 ] || models=(data/pretrained/pb4u.h5 data/pretrained/mgn.h5)
pb4u=${PB4U_BINARY:-build/pb4u}
[ -x "$pb4u" ] || { echo "stability_report.sh: $pb4u not built (scripts/build.sh)" >&2; exit 1; }

sets=()
[ -n "$split" ] && sets+=(--set "split=$split")
[ -n "$dataset" ] && sets+=(--set "dataset=$dataset")
[ $quick = 1 ] && sets+=(--set "levels=[1]" --set "garments=[tshirt]" --set max_sequences=1 --set max_frames=5)
sets+=("${extra[@]}")
checkpoints=()
for m in "${models[@]}"; do checkpoints+=(--checkpoint "$m"); done

mkdir -p "$out"
for case in body pinned; do
  config=configs/eval/heldout.yaml
  [ $case = pinned ] && config=configs/eval/heldout_pinned.yaml
  echo "stability_report.sh: $case ($config), ${#models[@]} network(s) and the reference solver" >&2
  start=$(date +%s)
  "$pb4u" --threads "$threads" evaluate "${checkpoints[@]}" --method reference --config "$config" \
    "${sets[@]}" --format json >"$out/$case.json.tmp"
  mv "$out/$case.json.tmp" "$out/$case.json"
  echo "stability_report.sh: $case took $(( $(date +%s) - start )) s" >&2
done

note="Configs: configs/eval/heldout.yaml (body) and heldout_pinned.yaml (pinned, no body)"
[ ${#sets[@]} -gt 0 ] && note+=", overrides: ${sets[*]}"
note+=". Networks: ${models[*]}. pb4u --threads $threads on a $(nproc --all)-core machine ($(date -u +%Y-%m-%d))."
/usr/bin/python3 scripts/stability_table.py "$out/body.json:body" "$out/pinned.json:pinned" --note "$note" \
  >"$out/report.md"
cat "$out/report.md"
