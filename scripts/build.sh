#!/usr/bin/env bash
# Configures (once) and builds pb4u and its tests in build/ (Release). Quiet on success.
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
if ! cmake --build "$BUILD_DIR" -j "$JOBS" >"$log" 2>&1; then
  grep -E 'error|Error|FAILED' "$log" | head -40 >&2
  echo "pb4u: build failed (full log: $log)" >&2
  exit 1
fi
rm -f "$log"
