#!/usr/bin/env bash
# The hard-case suite (tests/hard, ctest label `hard`) outside ctest.
# Usage:
#   scripts/hard_cases.sh [SCALE=4] [gtest filter]   rollouts SCALE times longer than in CI (4000
#                                                     frames for the long rollout at 4; the box keeps
#                                                     its 6, the held-out skirt its motion's 10) and
#                                                     lattices SCALE times the vertices a side (finer
#                                                     where a case divides the edge); the body cases
#                                                     keep their garments (the tiny dataset's level
#                                                     1; *AtTheTrainingEdge: configs/data/hard.yaml)
#   scripts/hard_cases.sh --known-gaps [SCALE=1]      the cases that miss their bounds today (the
#                                                     reference solver or the refined network;
#                                                     tests/hard/known_gaps.txt; ctest leaves them
#                                                     out): their figures and gtest's verdict
#   scripts/hard_cases.sh --step newton ...           either of the above with the reference
#                                                     solver's Newton step (physics.solver.step; the
#                                                     refinement takes Newton steps by default)
#   scripts/hard_cases.sh --solver KEY=VALUE[,...] ... physics.solver keys for the reference and
#                                                     the refinement, e.g. given_start=fewer_left_out
#                                                     (release_held_cloth is the reference's alone:
#                                                     the refinement keeps its own, on)
#   scripts/hard_cases.sh --refine KEY=VALUE[,...] ... the refinement's keys (refine.*), e.g.
#                                                     release_held_cloth=true; each run keeps its
#                                                     count and tolerance
#   scripts/hard_cases.sh --start settled ...         the body cases' first frame reached by the
#                                                     solver from the bind pose (scene key
#                                                     body.start; default: skinned)
# Prints one "[hard] ..." line per figure and gtest's verdict; exits non-zero when a case fails.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${PB4U_BUILD_DIR:-build}
# The options, in any order, before --known-gaps or SCALE.
while [ $# -gt 0 ]; do
  case "$1" in
    --step)
      case "${2:-}" in
        quasi_newton|newton) export PB4U_HARD_SOLVER_STEP=$2 ;;
        *) echo "hard_cases.sh: --step: '${2:-}' is not quasi_newton or newton" >&2; exit 2 ;;
      esac ;;
    --solver)
      [ -n "${2:-}" ] || { echo "hard_cases.sh: --solver needs KEY=VALUE[,KEY=VALUE...]" >&2; exit 2; }
      export PB4U_HARD_SOLVER=$2 ;;
    --refine)
      [ -n "${2:-}" ] || { echo "hard_cases.sh: --refine needs KEY=VALUE[,KEY=VALUE...]" >&2; exit 2; }
      export PB4U_HARD_REFINE=$2 ;;
    --start)
      case "${2:-}" in
        skinned|settled) export PB4U_HARD_START=$2 ;;
        *) echo "hard_cases.sh: --start: '${2:-}' is not skinned or settled" >&2; exit 2 ;;
      esac ;;
    *) break ;;
  esac
  shift 2
done
if [ "${1:-}" = "--known-gaps" ]; then
  SCALE=${2:-1}
  FILTER=$(grep -E '^[A-Za-z]' tests/hard/known_gaps.txt | paste -sd: -)
else
  SCALE=${1:-4}
  FILTER=${2:-*}
fi
cmake --build "$BUILD" --target hard_tests pb4u >/dev/null
PB4U_HARD_SCALE=$SCALE "$BUILD/tests/hard_tests" --gtest_filter="$FILTER" --gtest_color=no
