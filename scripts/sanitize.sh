#!/usr/bin/env bash
# The sanitizer job: builds the core, the unit tests, the CLI and the fuzz targets with clang
# under ASan+UBSan in their own build directory (no RTL, no benchmarks), then runs the unit and
# CLI tests and a short fuzz run of each target on its seed corpus.
#   scripts/sanitize.sh [--build-only] [BUILD_DIR=build-sanitize] [FUZZ_SECONDS=20]
set -euo pipefail
cd "$(dirname "$0")/.."
build_only=0
if [ "${1:-}" = "--build-only" ]; then build_only=1; shift; fi
build="${1:-build-sanitize}"
fuzz_secs="${2:-20}"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [ ! -f "$build/build.ninja" ]; then
  # -O1 and line tables only, as the sanitizers' documentation suggests: a sixth less compile
  # time than -O2 -g, and the reports still name file and line.
  CXX=clang++-14 cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
    -DRTUSIM_SANITIZE=ON -DRTUSIM_FUZZ=ON -DRTUSIM_BUILD_RTL=OFF -DRTUSIM_BUILD_BENCH=OFF \
    "${launcher[@]}" >/dev/null
fi
cmake --build "$build" --parallel "$(nproc)" --target rtusim rtusim_unit_tests fuzz_config fuzz_gltf fuzz_trace
[ "$build_only" = 1 ] && exit 0

export ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export RTUSIM_SCENES="${RTUSIM_SCENES:-$(cd .. && pwd)/shared/scenes}"
# cli.bad_input expects the RTL's own message for l1.model=rtl, and cli.registries runs every
# tier, rtl included: a build without the RTL cannot do either (the main build runs both;
# bad_input_catalogue covers bad_input's other cases here). cli.sweep_dask runs the binary's
# sweep path that cli.sweep runs here, under dask's scheduler: two minutes of the same code.
(cd "$build" && ctest --output-on-failure --parallel "$(nproc)" --timeout 900 -L 'unit|cli' -LE rtl \
   -E '^cli\.(bad_input|registries|sweep_dask)$')
bash scripts/fuzz.sh "$fuzz_secs" "$build"
