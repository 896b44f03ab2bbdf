#!/usr/bin/env bash
# Held-out stability report (issue 14, SPEC 9): the networks and the reference solver on the
# held-out evaluation, with a body (configs/eval/heldout.yaml) and pinned without one
# (configs/eval/heldout_pinned.yaml); a markdown table of each network against the solver on
# the same sequences (scripts/stability_table.py) to DIR/report.md and stdout.
#
# Usage: scripts/stability_report.sh [--quick | --reduced] [--networks-only] [--case body|pinned] [--out DIR]
#            [--split NAME] [--dataset FILE] [--threads N] [--set KEY=VALUE ...] [CHECKPOINT ...]
#   CHECKPOINT    networks to evaluate (default data/pretrained/pb4u.h5 data/pretrained/mgn.h5)
#   --quick       a smoke test: level 1, the t-shirt, one motion, 5 frames (minutes, not hours)
#   --reduced     what docs/robustness.md reports: level 1; the t-shirt, the skirt and the
#                 imported t-shirt; the first held-out motion of each body; 300 frames (~1 h)
#   --case C      only the body case or only the pinned one (default both)
#   --fresh       run the solver again even if DIR holds its run with the same settings
#   --networks-only  no solver: the networks' energies (J), penetration and divergence on the
#                 chosen set, e.g. every held-out motion at level 1 (--set levels=[1]: minutes)
#   --split NAME  motions of this split instead of "heldout" (e.g. test, for a dataset without it)
#   --dataset F   another generated dataset (default: the configs', data/generated/quick/quick.h5)
#   --threads N   torch threads for pb4u (default 1)
#   --set K=V     any evaluate-config override for both cases, e.g. --set levels=[1] (repeatable);
#                 --case body --set start=settled starts every method from the frame the solver
#                 reaches from the bind pose (docs/evaluation.md)
# The full run rolls the solver out for 300 frames per sequence: hours on a CPU. The solver does
# not depend on the networks, so its run is kept in DIR/<case>.reference.json beside the
# settings it ran with (config, overrides, dataset file, the pb4u binary's checksum) and reused
# while they match (a build whose solver or its defaults changed gets a fresh run); the
# networks' run goes to DIR/<case>.networks.json; the report is built from both.
set -euo pipefail
cd "$(dirname "$0")/.."
out=runs/stability quick=0 reduced=0 fresh=0 networks_only=0 cases="body pinned" split="" dataset="" threads=1 models=() extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --reduced) reduced=1 ;;
    --fresh) fresh=1 ;;
    --networks-only) networks_only=1 ;;
    --case) case $2 in body|pinned) cases=$2 ;; *) echo "stability_report.sh: --case body or pinned, not '$2'" >&2; exit 2 ;; esac; shift ;;
    --out) out=$2; shift ;;
    --split) split=$2; shift ;;
    --dataset) dataset=$2; shift ;;
    --threads) threads=$2; shift ;;
    --set) extra+=(--set "$2"); shift ;;
    -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;;
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
[ $reduced = 1 ] && sets+=(--set "levels=[1]" --set "garments=[tshirt,skirt,tshirt_file]" --set max_sequences=1)
[ ${#extra[@]} -gt 0 ] && sets+=("${extra[@]}")
checkpoints=()
for m in "${models[@]}"; do checkpoints+=(--checkpoint "$m"); done

mkdir -p "$out"
run_evaluate() {  # run_evaluate CASE OUTPUT ARGS...: evaluate into OUTPUT (atomically), timed
  local case=$1 output=$2
  shift 2
  local start
  start=$(date +%s)
  "$pb4u" --threads "$threads" evaluate "$@" --format json >"$output.tmp"
  mv "$output.tmp" "$output"
  echo "stability_report.sh: $case: $(basename "$output") took $(( $(date +%s) - start )) s" >&2
}
runs=()
for case in $cases; do
  config=configs/eval/heldout.yaml
  [ $case = pinned ] && config=configs/eval/heldout_pinned.yaml
  # The solver's run, reused while the config, the overrides, the dataset file (size and time)
  # and the binary (its checksum: a version number does not change with a solver's default) match.
  if [ $networks_only = 1 ]; then
    echo "stability_report.sh: $case ($config): ${#models[@]} network(s), no solver" >&2
    run_evaluate "$case" "$out/$case.networks.json" "${checkpoints[@]}" --config "$config" "${sets[@]}"
    runs+=("$out/$case.networks.json:$case")
    continue
  fi
  reference=$out/$case.reference.json
  data=${dataset:-$(sed -n 's/^dataset: *//p' "$config" | head -1)}
  settings="$config $(sha256sum "$config" | cut -c1-16) ${sets[*]} $data $(stat -c '%s %Y' "$data" 2>/dev/null) $("$pb4u" --version 2>&1 | tail -1) $(sha256sum "$(command -v "$pb4u")" | cut -c1-16)"
  if [ $fresh = 0 ] && [ -f "$reference" ] && [ "$(cat "$reference.settings" 2>/dev/null)" = "$settings" ]; then
    echo "stability_report.sh: $case: reusing the solver's run $reference" >&2
  else
    echo "stability_report.sh: $case ($config): the reference solver" >&2
    rm -f "$reference.settings"
    run_evaluate "$case" "$reference" --method reference --config "$config" "${sets[@]}"
    printf '%s' "$settings" >"$reference.settings"
  fi
  echo "stability_report.sh: $case ($config): ${#models[@]} network(s)" >&2
  run_evaluate "$case" "$out/$case.networks.json" "${checkpoints[@]}" --config "$config" "${sets[@]}"
  runs+=("$out/$case.networks.json,$reference:$case")
done

note="Configs: configs/eval/heldout.yaml (body) and heldout_pinned.yaml (pinned, no body)"
[ ${#sets[@]} -gt 0 ] && note+=", overrides: ${sets[*]}"
note+=". Networks: ${models[*]}. pb4u --threads $threads on a $(nproc --all)-core machine ($(date -u +%Y-%m-%d))."
table_args=()
[ $networks_only = 1 ] && table_args=(--no-reference)
python3 scripts/stability_table.py "${runs[@]}" "${table_args[@]}" --note "$note" >"$out/report.md"
cat "$out/report.md"
