#!/usr/bin/env bash
# One command from a fresh clone: install what is missing, build, run every test.
# Prints ctest's summary; exits non-zero if anything fails.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
ctest --test-dir "${PB4U_BUILD_DIR:-build}" -j "$(nproc)" --timeout 900 --output-on-failure "$@"
