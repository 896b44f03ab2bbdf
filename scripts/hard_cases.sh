#!/usr/bin/env bash
# The hard-case suite (tests/hard, ctest label `hard`) at a larger size: meshes SCALE times
# finer and rollouts SCALE times longer than in CI (4000 frames for the long rollout at 4).
# Usage: scripts/hard_cases.sh [SCALE=4] [gtest filter]
# Prints one "[hard] case / method: frames, vertices, max stretch, max total energy, max speed,
# seconds" line per rollout and gtest's verdict.
set -euo pipefail
cd "$(dirname "$0")/.."
SCALE=${1:-4}
FILTER=${2:-*}
ninja -C build hard_tests pb4u >/dev/null
PB4U_HARD_SCALE=$SCALE build/tests/hard_tests --gtest_filter="$FILTER" --gtest_color=no
