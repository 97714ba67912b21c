#!/usr/bin/env bash
# Runs the whole test suite: set-up and build (idempotent), then every ctest label.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export RTUSIM_SCENES="${RTUSIM_SCENES:-$(cd .. && pwd)/shared/scenes}"
cd build
ctest --output-on-failure --parallel "$(nproc)" --timeout 900 "$@"
