#!/usr/bin/env bash
# Configures (once) and builds pb4u and its tests in build/ (Release). Shows progress (one
# updating line on a terminal, a line per 10% otherwise); the full log only on failure.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${PB4U_BUILD_DIR:-build}
JOBS=${PB4U_JOBS:-$(nproc)}
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  generator=()
  command -v ninja >/dev/null && generator=(-G Ninja)
  cmake -S . -B "$BUILD_DIR" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >"$BUILD_DIR.configure.log" 2>&1 ||
    { cat "$BUILD_DIR.configure.log" >&2; exit 1; }
  rm -f "$BUILD_DIR.configure.log"
fi
log=$(mktemp)
# Ninja prints "[k/N] ..." and Make "[ p%] ..." per step: the log gets every line, the
# screen a progress line (rewritten in place on a terminal, one per 10% otherwise).
progress() {
  local tty=$1 start=$SECONDS next=0 pct what elapsed eta line
  while IFS= read -r out; do
    printf '%s\n' "$out" >>"$log"
    if [[ $out =~ ^\[([0-9]+)/([0-9]+)\] ]]; then
      pct=$((100 * BASH_REMATCH[1] / BASH_REMATCH[2])); what="${BASH_REMATCH[1]}/${BASH_REMATCH[2]} steps"
    elif [[ $out =~ ^\[\ *([0-9]+)%\] ]]; then
      pct=${BASH_REMATCH[1]}; what="make"
    else
      continue
    fi
    elapsed=$((SECONDS - start)); eta=""
    ((pct > 2 && pct < 100)) && eta=", about $(((elapsed * (100 - pct) / pct + 59) / 60)) min left"
    line=$(printf 'build: %3d%% (%s), %d:%02d elapsed%s' "$pct" "$what" $((elapsed / 60)) $((elapsed % 60)) "$eta")
    if [ "$tty" = 1 ]; then
      printf '\r%-78s' "$line"
    elif ((pct >= next)); then
      echo "$line"; next=$((pct - pct % 10 + 10))
    fi
  done
  [ "$tty" = 1 ] && [ -n "${line:-}" ] && echo
  return 0
}
tty=0
[ -t 1 ] && tty=1
todo=$(cmake --build "$BUILD_DIR" -- -n 2>/dev/null | grep -c '^\[' || true)
if [ "$todo" -gt 20 ]; then
  echo "build: $todo steps to run in $BUILD_DIR with $JOBS jobs (a first build takes about 9 minutes on 2 cores)"
fi
set +o pipefail
cmake --build "$BUILD_DIR" -j "$JOBS" 2>&1 | progress "$tty"
status=${PIPESTATUS[0]}
set -o pipefail
if [ "$status" -ne 0 ]; then
  grep -E 'error|Error|FAILED' "$log" | head -40 >&2
  echo "pb4u: build failed (full log: $log)" >&2
  exit 1
fi
rm -f "$log"
