#!/usr/bin/env bash
# Data-parallel training on this machine: starts N ranks of `pb4u train` (Gloo on loopback),
# each with cores/N torch threads, and waits for all of them. Every argument after N goes to
# every rank (--config, --set, --out, --resume, --timeout ...). Rank 0 writes the run.
#
#   scripts/train_ddp.sh 2 --config configs/train/quick.yaml --out runs/quick_ddp
#   scripts/train_ddp.sh 2 --config configs/train/quick.yaml --out runs/quick_ddp --resume
#
# Environment: PB4U (binary, default build/pb4u), MASTER_PORT (default 29500),
# THREADS (torch threads per rank, default max(1, nproc / N)).
# The script exits with the first failing rank's status; a rank that dies makes the others
# stop within --timeout (default 300 s), and the script then stops any that remain.
set -uo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ] || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: $0 N [pb4u train options...]" >&2
  exit 2
fi
n=$1
shift
bin=${PB4U:-build/pb4u}
port=${MASTER_PORT:-29500}
threads=${THREADS:-$(( $(nproc) / n > 0 ? $(nproc) / n : 1 ))}
[ -x "$bin" ] || { echo "$0: $bin not found; build first (scripts/build.sh) or set PB4U" >&2; exit 2; }

pids=()
stop_all() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done; }
trap 'stop_all; exit 130' INT TERM
for ((r = 0; r < n; ++r)); do
  quiet=()
  [ "$r" -gt 0 ] && quiet=(-q)  # one progress bar: rank 0's
  "$bin" "${quiet[@]}" --threads "$threads" train "$@" \
    --world-size "$n" --rank "$r" --master "127.0.0.1:$port" &
  pids+=($!)
done

status=0
remaining=$n
while [ "$remaining" -gt 0 ]; do
  wait -n
  rc=$?
  remaining=$((remaining - 1))
  if [ "$rc" -ne 0 ] && [ "$status" -eq 0 ]; then
    status=$rc
    echo "$0: a rank failed (exit $rc); the others stop within their --timeout" >&2
  fi
done
exit "$status"
