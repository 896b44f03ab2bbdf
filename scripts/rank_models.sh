#!/usr/bin/env bash
# Ranks training runs on a fixed probe set, kept apart from the held-out report
# (scripts/stability_report.sh), before any recipe is chosen (docs/training.md, "Ranking runs").
# Every checkpoint of a run is measured twice: the network alone (the shipped Pb4U's
# `update_scaling=detail` where the model was trained with update scaling, off where it was
# trained without; no contact projection, no strain limit, no refinement) and with the
# shipped file's passes (`contact_projection=0.002`, `strain_limit=0.1`). A run's row is the
# mean of its checkpoints and their spread (min-max), so that two recipes are told apart only
# when their difference exceeds the noise between checkpoints of one run.
#
# The probes (1 thread, quick dataset):
#   one step  evaluate: the t-shirt and tank top on their first training motions, level 1, frames
#             20-23 (configs/eval/quick.yaml, split train): stretch and collision, J per frame
#   walk      simulate configs/scenes/tshirt_walk.yaml (a training motion), 60 frames
#   hang      simulate configs/scenes/hanging_cloth.yaml (no body, pinned), 60 frames
#   unseen    evaluate: the t-shirt on the test split's first motion (run_1: never trained on,
#             not in the held-out report), 90 frames, at level 1 and the finest level 5
#   skirt     evaluate: the skirt, held at the waist, on the same motion, level 1, 90 frames
#             (since 2026-11-27: the t-shirt probes ranked two files above the shipped one that
#             the held-out skirt then ranked below it, docs/training.md)
# Each gives the positive energy (stretch + bending + collision) per frame, mean over frames;
# the walks also the largest share of vertices inside the body. A rollout that diverges is
# marked and ranks last. The score is the geometric mean of the six positive energies (the one
# step's stretch + collision standing for its own; five before the skirt); lower is better.
#
# Usage: scripts/rank_models.sh [--out DIR] [--last N] [--threads N] [--jobs N] [--reference] [--quick] RUN [RUN ...]
#   RUN          NAME=PATH[,PATH...] or PATH. PATH is a run directory (its newest N checkpoints
#                checkpoints/step_*.pt) or a model file (.pt or .h5); a run with several paths is
#                one run of several checkpoints (or seeds)
#   --out DIR    where exported files, per-probe results and rank.md go (default runs/rank)
#   --last N     checkpoints taken from a run directory (default 3)
#   --threads N  torch threads (default 1)
#   --jobs N     model files probed at once (default 1; 2 on two idle cores halves the time)
#   --reference  also the reference solver (pb4u >= 0.2: intersection-free) on the one step, walk, hang,
#                unseen level 1 and skirt (minutes; kept in DIR/reference and reused while the dataset
#                is the same file), and each probe's ratio to it
#   --quick      a smoke test: 3 frames per rollout, levels 1 and 2 (seconds, not minutes)
# A model's probes are kept in DIR too and reused while the dataset and its file are unchanged.
set -euo pipefail
cd "$(dirname "$0")/.."
out=runs/rank last=3 threads=1 jobs=1 reference=0 quick=0 runs=()
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=$2; shift ;;
    --last) last=$2; shift ;;
    --threads) threads=$2; shift ;;
    --jobs) jobs=$2; shift ;;
    --reference) reference=1 ;;
    --quick) quick=1 ;;
    -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;;
    -*) echo "rank_models.sh: unknown option $1" >&2; exit 2 ;;
    *) runs+=("$1") ;;
  esac
  shift
done
[ ${#runs[@]} -gt 0 ] || { echo "rank_models.sh: name at least one run (--help)" >&2; exit 2; }
pb4u=${PB4U_BINARY:-build/pb4u}
[ -x "$pb4u" ] || { echo "rank_models.sh: $pb4u not built (scripts/build.sh)" >&2; exit 1; }

walk_frames=60 hang_frames=60 unseen_frames=90 step_frames=4 finest=5
if [ $quick = 1 ]; then walk_frames=3 hang_frames=3 unseen_frames=3 step_frames=1 finest=2; fi
mkdir -p "$out"

# members RUN: the model files of one run, one per line.
members() {
  local spec=$1 paths p parts
  paths=${spec#*=}
  IFS=, read -r -a parts <<<"$paths"
  for p in "${parts[@]}"; do
    if [ -d "$p" ]; then
      local found
      found=$(ls "$p"/checkpoints/step_*.pt 2>/dev/null | sort | tail -n "$last")
      [ -n "$found" ] || { echo "rank_models.sh: $p holds no checkpoints/step_*.pt" >&2; exit 1; }
      echo "$found"
    elif [ -f "$p" ]; then
      echo "$p"
    else
      echo "rank_models.sh: $p: no such run directory or model file" >&2; exit 1
    fi
  done
}
run_name() {  # NAME=... gives NAME; a bare path its base name
  local spec=$1
  if [[ "$spec" == *=* ]]; then echo "${spec%%=*}"; else basename "${spec%/}" | sed 's/\.[a-z0-9]*$//'; fi
}

# probe MODEL DIR [SOURCE]: the probes of one model file (or "reference", the solver) into DIR;
# a probe whose result DIR already holds is not run again while the dataset and SOURCE (the file
# MODEL was exported from; default MODEL) are those it was run on (their size and time in
# DIR/stamp, with pb4u's version: a regenerated dataset, a new file under the same name or
# another version clears DIR).
probe() {
  local model=$1 dir=$2 source=${3:-$1} method=() scene name file frames
  local stamp
  stamp="$(stat -c '%s %Y' data/generated/quick/quick.h5 2>/dev/null) $( [ "$model" = reference ] || stat -c '%s %Y' "$source") $("$pb4u" --version 2>&1 | tail -1)"
  if [ "$(cat "$dir/stamp" 2>/dev/null)" != "$stamp" ]; then rm -rf "$dir"; fi
  mkdir -p "$dir"
  printf '%s' "$stamp" >"$dir/stamp"
  if [ "$model" = reference ]; then method=(--method reference); else method=(--checkpoint "$model"); fi
  local t="$pb4u --threads $threads -q"
  if [ ! -s "$dir/step.json" ]; then
    $t evaluate "${method[@]}" --config configs/eval/quick.yaml --set split=train --set 'levels=[1]' \
      --set start_frame=20 --set max_frames=$step_frames --format json >"$dir/step.json.tmp"
    mv "$dir/step.json.tmp" "$dir/step.json"
  fi
  for scene in walk:tshirt_walk:$walk_frames hang:hanging_cloth:$hang_frames; do
    IFS=: read -r name file frames <<<"$scene"
    [ -s "$dir/$name/energies.csv" ] && continue
    local method_sim=(--method net --checkpoint "$model")
    [ "$model" = reference ] && method_sim=(--method reference)
    # A rollout that diverges stops early: its energies.csv is short, which the table reads.
    $t simulate "${method_sim[@]}" --scene configs/scenes/$file.yaml --frames "$frames" --format none \
      --preview off --out "$dir/$name.tmp" >/dev/null 2>"$dir/$name.log" || true
    mkdir -p "$dir/$name.tmp"
    echo "$frames" >"$dir/$name.tmp/requested_frames"
    rm -rf "$dir/$name"; mv "$dir/$name.tmp" "$dir/$name"
  done
  local levels="[1,$finest]"
  [ "$model" = reference ] && levels="[1]"
  if [ ! -s "$dir/unseen.json" ]; then
    $t evaluate "${method[@]}" --config configs/eval/heldout.yaml --set split=test --set "levels=$levels" \
      --set 'garments=[tshirt]' --set max_sequences=1 --set max_frames=$unseen_frames --format json >"$dir/unseen.json.tmp"
    mv "$dir/unseen.json.tmp" "$dir/unseen.json"
  fi
  if [ ! -s "$dir/skirt.json" ]; then  # the skirt held at the waist (heldout.yaml's waistband)
    $t evaluate "${method[@]}" --config configs/eval/heldout.yaml --set split=test --set 'levels=[1]' \
      --set 'garments=[skirt]' --set max_sequences=1 --set max_frames=$unseen_frames --format json >"$dir/skirt.json.tmp"
    mv "$dir/skirt.json.tmp" "$dir/skirt.json"
  fi
}

# Up to --jobs probe sets at once; a failed one fails the script once all have ended.
pids=() failed=0
in_background() {
  "$@" &
  pids+=($!)
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || failed=1; done
}
wait_all() {
  for pid in "${pids[@]}"; do wait "$pid" || failed=1; done
  [ $failed = 0 ] || { echo "rank_models.sh: a probe failed (its log is in its member's directory)" >&2; exit 1; }
}

args=()
start=$(date +%s)
for spec in "${runs[@]}"; do
  name=$(run_name "$spec")
  files=$(members "$spec")
  i=0
  while IFS= read -r f; do
    i=$((i + 1))
    member="$out/models/$name/$i"
    # Probes are kept per member and reused, unless the member is now another file.
    if [ -f "$member/source" ] && [ "$(cat "$member/source")" != "$f" ]; then rm -rf "$member"; fi
    mkdir -p "$member"
    echo "$f" >"$member/source"
    # The shipped Pb4U's detail update scaling for models trained with update scaling; a model
    # trained without it (MGN, HOOD, CCRAFT, ESLR) keeps it off, as it was trained.
    scaling=(--set update_scaling=detail)
    if "$pb4u" -q inspect "$f" | grep -Eq '^  update_scaling: "?off"?$'; then scaling=(); fi
    "$pb4u" -q export --checkpoint "$f" "${scaling[@]}" --set contact_projection=0 \
      --set strain_limit=0 --set refine_iterations=0 --out "$member/alone.h5"
    "$pb4u" -q export --checkpoint "$f" "${scaling[@]}" --set contact_projection=0.002 \
      --set strain_limit=0.1 --set refine_iterations=0 --out "$member/passes.h5"
    for variant in alone passes; do
      echo "rank_models.sh: $name #$i ($f), $variant ($(( $(date +%s) - start )) s so far)" >&2
      in_background probe "$member/$variant.h5" "$member/$variant" "$f"
      args+=("$name:$i:$variant:$member/$variant")
    done
  done <<<"$files"
done
if [ $reference = 1 ]; then
  echo "rank_models.sh: the reference solver ($(( $(date +%s) - start )) s so far)" >&2
  in_background probe reference "$out/reference"
  args+=(--reference "$out/reference")
fi
wait_all
python3 scripts/rank_table.py "${args[@]}" --json "$out/rank.json" >"$out/rank.md"
cat "$out/rank.md"
echo "rank_models.sh: $(( $(date +%s) - start )) s; table in $out/rank.md" >&2
