#!/usr/bin/env bash
# Rewrites traces/*/expected.json from the current build: run it only when a change of the
# reference numbers is intended, and commit the new files with a message that says why.
# No test calls it. Usage: scripts/update_references.sh [BUILD_DIR] (default build/).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
export RTUSIM_SCENES="${RTUSIM_SCENES:-$(cd .. && pwd)/shared/scenes}"
cmake --build "$build" --target rtusim
"$build/rtusim" regress traces --update
git --no-pager diff --stat -- traces || true
