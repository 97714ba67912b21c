#!/usr/bin/env bash
# Runs the whole test suite: set-up and build (idempotent), then every ctest label.
# Usage: scripts/test.sh [CTEST_ARGS...]  (e.g. -L stability, -R sweep)
set -euo pipefail
case "${1:-}" in -h|--help) sed -n '2,3p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;; esac
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export RTUSIM_SCENES="${RTUSIM_SCENES:-$(cd .. && pwd)/shared/scenes}"
cd build
ctest --output-on-failure --parallel "$(nproc)" --timeout 900 "$@"
