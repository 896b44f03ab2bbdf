#!/usr/bin/env bash
# The GPU machine's checks of docs/cuda.md in one run, each phase skipped once the time is short:
#   1. scripts/device_build.sh: build against PyTorch's LibTorch (CUDA) and run the whole ctest;
#   2. training steps per second with run.device=cuda (quick config, then the paper-size model)
#      on the quick dataset;
#   3. Table 3 at paper scale: the paper-size model (width 128, 15 blocks, K_base 15; a few
#      training steps only: timing does not depend on the weights) on the t-shirt remeshed to
#      ~12K, 25K and 48K triangles on the quick dataset's walking CMU body, `simulate --device cuda`.
#      The network step per frame is the step-time sum over frames 11-40 (from the summaries of a
#      10- and a 40-frame run) over 30, so CUDA's warm-up and the CPU's per-frame energies are out;
#   4. with --capacity-steps N: quick.yaml's recipe from scratch at three model sizes (latent x
#      blocks: quick 64 x 4, mid 96 x 8, paper 128 x 15), N steps each, the three at once on the
#      device while the rest of the suite runs on the CPU; their last three checkpoints are
#      exported (model files) into DIR/capacity_*.tgz (the paper size's newest two beside them, 16 MB
#      each) for scripts/rank_models.sh; with --capacity-resumable, each run's directory with its
#      newest training checkpoint instead (DIR/capacity_NAME.tar.partNN, 15 MiB pieces: the paper
#      size's is 49 MB with Adam's state), to go on with `train --resume` elsewhere:
#        cat capacity_paper.tar.part* | tar -x -C runs/   # then: train ... --out runs/capacity_paper --resume
#
#   scripts/device_checks.sh [--out DIR] [--budget SECONDS] [--jobs N] [--skip-build]
#                            [--device D] [--triangles "N ..."] [--train-steps "QUICK PAPER"]
#                            [--capacity-steps N] [--capacity-sizes "NAME ..."]
#                            [--capacity-set KEY=VALUE ...] [--capacity-resumable] [--skip-timings]
#
#   --budget SECONDS  phases that would start with too little of it left are skipped (default 540)
#   --skip-build      use an existing build-cuda/ (PB4U=path overrides the binary)
#   --device D        where training and the network run (default cuda; cpu checks the script)
#   --triangles       Table 3's garment sizes (default "12000 25000 48000")
#   --train-steps     training steps timed (default "300 100"); each config is also profiled
#                     (`train --profile`) over a third of them
#   --capacity-steps  steps of each capacity run (default 0: none)
#   --capacity-sizes  which of quick, mid, paper (default all three)
#   --capacity-set    a training config override for every capacity run (repeatable), e.g.
#                     physics.collision.hold_steps=250 for a recipe compressed to fit the budget
#   --capacity-resumable  bring back each run's directory and newest checkpoint, not model files;
#                     the logs come back as DIR/logs.tgz (at most 8 files come back from a device)
#   --skip-timings    no training speed, profile or Table 3 (phases 2-3): when the network's code
#                     has not changed since their last figures, the budget goes to capacity
# Needs device_bundle/debs (scripts/device_bundle.sh) and data/generated/quick/quick.h5 carried
# along. Results: DIR/device_checks.txt and DIR/logs/ (configure, build, ctest logs).
set -uo pipefail
cd "$(dirname "$0")/.."
root=$PWD
out=${OUT:-runs/device} budget=540 jobs=$(nproc) build_step=1 device=cuda triangles="12000 25000 48000" steps="300 100" capacity_steps=0
timings=1 capacity_names="quick mid paper" capacity_sets=() resumable=0
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=$2; shift ;;
    --budget) budget=$2; shift ;;
    --jobs) jobs=$2; shift ;;
    --skip-build) build_step=0 ;;
    --device) device=$2; shift ;;
    --triangles) triangles=$2; shift ;;
    --train-steps) steps=$2; shift ;;
    --capacity-steps) capacity_steps=$2; shift ;;
    --capacity-sizes) capacity_names=$2; shift ;;
    --capacity-set) capacity_sets+=(--set "$2"); shift ;;
    --skip-timings) timings=0 ;;
    --capacity-resumable) resumable=1 ;;
    -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "device_checks: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
capacity_sizes=()
for size in "quick 64 4" "mid 96 8" "paper 128 15"; do
  case " $capacity_names " in *" ${size%% *} "*) capacity_sizes+=("$size") ;; esac
done
if [ "$capacity_steps" -gt 0 ] && [ ${#capacity_sizes[@]} = 0 ]; then
  echo "device_checks: --capacity-sizes '$capacity_names': none of quick, mid, paper" >&2; exit 2
fi
mkdir -p "$out/logs"
report=$out/device_checks.txt
say() { echo "device_checks: $*" | tee -a "$report"; }
left() { echo $((budget - SECONDS)); }
now() { date +%s.%N; }
dataset=$root/data/generated/quick/quick.h5
[ -f "$dataset" ] || { say "no $dataset: carry data/generated/quick"; exit 1; }
: >"$report"
command -v nvidia-smi >/dev/null && say "GPU: $(nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader | head -n1)"
say "CPU: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"

# 1. Build (tests last, so that the figures come back even when the suite runs long).
if [ "$build_step" = 1 ]; then
  t0=$SECONDS
  scripts/device_build.sh --jobs "$jobs" --logs "$out/logs" --no-tests >"$out/logs/device_build_stdout.log" 2>&1
  say "build: exit $? in $((SECONDS - t0)) s"
fi
pb4u=${PB4U:-$root/build-cuda/pb4u}
[ -x "$pb4u" ] || { say "no $pb4u: the build failed"; exit 1; }
torch_lib=$(python3 2>/dev/null -c 'import torch, os; print(os.path.join(os.path.dirname(torch.__file__), "lib"))')
export LD_LIBRARY_PATH=$torch_lib:$root/device_bundle/prefix/usr/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}

ctest_run() {  # NAME SECONDS ctest-arguments...: the summary and every failure into the report
  local name=$1 limit=$2
  shift 2
  local t0=$SECONDS
  timeout "$limit" ctest --test-dir "$root/build-cuda" -j "$jobs" --timeout 300 --output-on-failure "$@" \
    >"$out/logs/ctest_$name.log" 2>&1
  say "ctest $name: exit $? in $((SECONDS - t0)) s"
  grep -E 'tests passed|tests failed|Total Test time|[0-9]+ - .*\((Failed|SEGFAULT|Timeout|Subprocess aborted|Skipped|Not Run|Exception)\)' "$out/logs/ctest_$name.log" \
    | head -n 40 | tee -a "$report"
}
[ -d "$root/build-cuda" ] && ctest_run cuda 120 -L cuda -V

# 2. Training steps per second (wall time of `pb4u train`, start-up included).
train() {  # NAME CONFIG STEPS [--set ...]
  local name=$1 config=$2 steps=$3
  shift 3
  local t0 t1
  rm -rf "/tmp/device_train_$name"
  t0=$(now)
  "$pb4u" -q train --config "$config" --out "/tmp/device_train_$name" --set run.device="$device" --set run.steps="$steps" \
    --set data.dataset="$dataset" --set run.checkpoint_every="$steps" "$@" >"/tmp/device_train_$name.log" 2>&1
  local rc=$?
  t1=$(now)
  say "train $name: exit $rc, $(awk -v a="$t0" -v b="$t1" -v n="$steps" 'BEGIN { printf "%d steps in %.1f s: %.2f steps/s", n, b - a, n / (b - a) }') ($device, start-up included)"
  [ $rc = 0 ] || tail -n 5 "/tmp/device_train_$name.log" | tee -a "$report"
}
if [ "$timings" = 0 ]; then
  say "skipped training speed and Table 3 (--skip-timings)"
elif [ "$(left)" -gt 120 ]; then
  read -r quick_steps paper_steps <<<"$steps"
  train quick configs/train/quick.yaml "$quick_steps"
  train paper configs/train/paper.yaml "$paper_steps"
  for config in quick paper; do  # where a step's time goes, on this device
    [ "$config" = quick ] && n=$((quick_steps / 3)) || n=$((paper_steps / 3))
    rm -rf "/tmp/device_profile_$config"
    "$pb4u" -q train --profile --config "configs/train/$config.yaml" --out "/tmp/device_profile_$config" \
      --set run.device="$device" --set run.steps="$n" --set data.dataset="$dataset" --set run.checkpoint_every="$n" \
      >"/tmp/device_profile_$config.log" 2>&1 || say "train --profile $config failed"
    say "profile $config, $n steps:"
    sed -n '/Training step profile/,$p' "/tmp/device_profile_$config.log" | tee -a "$report"
  done
else
  say "skipped training: $(left) s left"
fi

# 3. Table 3 at paper scale.
model=/tmp/device_train_paper/final.pt
step_sum() {  # LOG -> frames x mean step ms, from the summary "N frames: ... X ms per frame"
  sed -nE 's/.* ([0-9]+) frames: .* ([0-9.]+) ms per frame.*/\1 \2/p' "$1" | tail -n1 | awk '{ printf "%.3f", $1 * $2 }'
}
if [ "$timings" = 0 ]; then
  :
elif [ -f "$model" ]; then
  say "Table 3, paper-size model, t-shirt on the quick dataset's walking CMU body, simulate --device $device"
  say "| triangles (asked) | vertices | network step ms/frame (frames 11-40) | wall ms/frame (40 minus 10 frames) | positive energy mean J (40 frames) |"
  need=90  # seconds a size must have left: 90 for the first, then twice the last size's time
  for tri in $triangles; do
    [ "$(left)" -gt "$need" ] || { say "skipped $tri and finer: $(left) s left, $need s wanted"; break; }
    size_start=$SECONDS
    scene=/tmp/device_table3_$tri.yaml
    cat >"$scene" <<EOF
frames: 40
effects: [gravity, collision, friction]
garment:
  source: file
  file: $root/data/meshes/tshirt.obj
  triangles: $tri
body:
  dataset: $dataset
  name: cmu131
  motion: $root/data/mocap/cmu_131_01.bvh
  bvh_scale: 1.0
outputs:
  mesh_format: none
  preview: false
  residual: false   # a solver step per frame on the CPU: not the network's time
divergence:
  energy_ratio: 0   # a barely trained model: time 40 frames whatever its energy does
EOF
    declare -A wall sum
    for frames in 10 40; do
      log=/tmp/device_table3_${tri}_$frames.log
      t0=$(now)
      "$pb4u" simulate --checkpoint "$model" --scene "$scene" --out "/tmp/device_table3_${tri}_$frames" \
        --frames "$frames" --device "$device" >"$log" 2>&1 || { say "simulate $tri x $frames failed:"; tail -n 3 "$log" | tee -a "$report"; }
      t1=$(now)
      wall[$frames]=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')
      sum[$frames]=$(step_sum "$log")
    done
    vertices=$(od -An -t d4 -j 16 -N 4 "/tmp/device_table3_${tri}_40/garment.pc2" 2>/dev/null | tr -d ' ')  # PC2: point count at byte 16
    energy=$(sed -nE 's/.* frames: positive energy mean ([^ ]+) J.*/\1/p' /tmp/device_table3_${tri}_40.log | tail -n1)
    say "| $tri | ${vertices:-?} | $(awk -v a="${sum[10]:-0}" -v b="${sum[40]:-0}" 'BEGIN { printf "%.1f", (b - a) / 30 }') | $(awk -v a="${wall[10]}" -v b="${wall[40]}" 'BEGIN { printf "%.1f", 1000 * (b - a) / 30 }') | ${energy:-?} |"
    need=$((2 * (SECONDS - size_start) + 30))
  done
else
  say "skipped Table 3: no paper-size model ($model)"
fi
# 4. Capacity runs on the device (started here, collected after the suite).
if [ "$capacity_steps" -gt 0 ]; then
  rm -f /tmp/capacity_*.done
  for size in "${capacity_sizes[@]}"; do
    read -r name latent blocks <<<"$size"
    rm -rf "/tmp/capacity_$name" "/tmp/capacity_$name.done"
    ( t0=$(now)
      "$pb4u" -q --threads 2 train --config configs/train/quick.yaml --out "/tmp/capacity_$name" \
        --set run.device="$device" --set run.steps="$capacity_steps" --set data.dataset="$dataset" \
        --set run.checkpoint_every=$((capacity_steps / 4)) --set run.keep_checkpoints=3 \
        --set model.latent="$latent" --set model.num_blocks="$blocks" "${capacity_sets[@]}" \
        >"/tmp/capacity_$name.log" 2>&1
      echo "$? $(awk -v a="$t0" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }')" >"/tmp/capacity_$name.done" ) &
  done
  say "capacity: quick.yaml's recipe${capacity_sets:+ with ${capacity_sets[*]}}, $capacity_steps steps each, sizes ${capacity_sizes[*]}, at once on $device"
fi

# 5. The whole suite but the cuda label, in what is left.
if [ -d "$root/build-cuda" ] && [ "$(left)" -gt 30 ]; then
  [ "$capacity_steps" -gt 0 ] && suite_jobs=$((jobs > 12 ? jobs - 6 : jobs)) || suite_jobs=$jobs
  jobs=$suite_jobs; ctest_run all $(($(left) - 40)) -LE cuda
else
  say "skipped the whole suite: $(left) s left"
fi

# The capacity runs: wait while time is left, then export what each run reached.
if [ "$capacity_steps" -gt 0 ]; then
  while [ "$(left)" -gt 25 ] && [ "$(ls /tmp/capacity_*.done 2>/dev/null | wc -l)" -lt ${#capacity_sizes[@]} ]; do sleep 2; done
  pkill -f "/tmp/capacity_" 2>/dev/null
  for size in "${capacity_sizes[@]}"; do
    read -r name latent blocks <<<"$size"
    dir=/tmp/capacity_$name
    read -r rc seconds 2>/dev/null <"$dir.done" || { rc=killed; seconds=$SECONDS; }
    reached=$(grep -c '"step"' "$dir/metrics.jsonl" 2>/dev/null)
    say "capacity $name ($latent x $blocks): exit $rc, ${reached:-0} steps in $seconds s"
    if [ "$resumable" = 1 ]; then  # the run directory with its newest checkpoint, in pieces
      newest=$(ls "$dir"/checkpoints/step_*.pt 2>/dev/null | tail -n 1)
      [ -n "$newest" ] || { say "capacity $name: no checkpoint written"; continue; }
      say "capacity $name: brought back $(basename "$newest") as capacity_$name.tar.part*"
      tar -C /tmp -cf - "capacity_$name/config.yaml" "capacity_$name/metrics.jsonl" \
        "capacity_$name/checkpoints/$(basename "$newest")" | split -b 15M -d - "$out/capacity_$name.tar.part"
      continue
    fi
    mkdir -p "$dir/export"
    for ckpt in "$dir"/checkpoints/step_*.pt; do
      [ -f "$ckpt" ] && "$pb4u" -q export --checkpoint "$ckpt" --out "$dir/export/${name}_$(basename "$ckpt" .pt).h5" >/dev/null 2>&1
    done
    tail -n 3 "$dir.log" >"$dir/export/train_tail.log" 2>/dev/null
    cp "$dir/metrics.jsonl" "$dir/config.yaml" "$dir/export/" 2>/dev/null
    if [ "$name" = paper ]; then  # 16 MB a model file: the newest two (three when it trains alone)
      keep=$(( ${#capacity_sizes[@]} == 1 ? 3 : 2 ))
      ls "$dir"/export/*.h5 2>/dev/null | head -n -"$keep" | xargs -r rm -f
      for f in "$dir"/export/*.h5; do [ -f "$f" ] && mv "$f" "$out/capacity_$(basename "$f")"; done
    fi
    tar -C "$dir/export" -czf "$out/capacity_$name.tgz" .
  done
fi
if [ "$resumable" = 1 ]; then tar -C "$out" -czf "$out/logs.tgz" logs && rm -rf "$out/logs"; fi
say "done in $SECONDS s"
