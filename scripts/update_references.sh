#!/usr/bin/env bash
# Rewrites traces/*/expected.json from the current build: run it only when a change of the
# reference numbers is intended, and commit the new files with a message that says why.
# No test calls it. Usage: scripts/update_references.sh [BUILD_DIR] (default build/).
set -euo pipefail
case "${1:-}" in -h|--help) sed -n '2,4p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;; esac
cd "$(dirname "$0")/.."
build=${1:-build}
[ -f "$build/CMakeCache.txt" ] || { echo "update_references.sh: $build: not a build directory" >&2; exit 2; }
export RTUSIM_SCENES="${RTUSIM_SCENES:-$(cd .. && pwd)/shared/scenes}"
cmake --build "$build" --target rtusim
"$build/rtusim" regress traces --update
git --no-pager diff --stat -- traces || true
