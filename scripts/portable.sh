#!/usr/bin/env bash
# The portable build's job: rtusim built for any x86-64 (RTUSIM_NATIVE=OFF: no -march=native;
# no RTL, no benchmarks; -Og) in its own build directory. It must compile (the native build
# takes other code paths: AVX2 and AVX-512 packets, pext, the replay's vector cache), pass the
# reference cases, and give the native build's stats.json (timings aside) on a functional, a
# timed-mode and a cycle-tier run: results do not depend on the host's instruction set or the
# optimisation level.
#   scripts/portable.sh [BUILD_DIR=build-portable] [NATIVE_BUILD_DIR=build]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build-portable}"
native="${2:-build}"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [ ! -f "$build/build.ninja" ]; then
  # -Og: half the compile time of -O3, and results must not depend on the optimisation level
  # either (no -ffast-math; -ffp-contract=off everywhere).
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_CXX_FLAGS_RELEASE="-Og -DNDEBUG" -DRTUSIM_NATIVE=OFF -DRTUSIM_BUILD_RTL=OFF \
    -DRTUSIM_BUILD_BENCH=OFF "${launcher[@]}" >/dev/null
fi
cmake --build "$build" --parallel "$(nproc)" --target rtusim
"$build/rtusim" regress

tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
w=(--set image.width=48 --set image.height=48 --set image.heatmaps=false --set image.png=false)
runs=("functional:" "timed:--set tracer.ray_order=wavefront --set functional.timed=true --set functional.rays_in_flight=8"
      "cycle:--set tracer.ray_order=wavefront --set sim.tier=cycle")
for r in "${runs[@]}"; do
  name=${r%%:*}; read -r -a extra <<< "${r#*:}"
  for b in "$native" "$build"; do
    "$b/rtusim" run configs/default.toml "${w[@]}" "${extra[@]}" --out "$tmp/$name-$(basename "$b")" > /dev/null
  done
done
python3 - "$tmp" "$(basename "$native")" "$(basename "$build")" <<'PY'
import json, sys
d, a, b = sys.argv[1:]
def results(path):
    s = json.load(open(path))
    return {k: v for k, v in s.items() if "seconds" not in k and "per_second" not in k}
for name in ["functional", "timed", "cycle"]:
    x, y = results(f"{d}/{name}-{a}/stats.json"), results(f"{d}/{name}-{b}/stats.json")
    diff = sorted(k for k in x.keys() | y.keys() if x.get(k) != y.get(k))
    assert not diff, f"portable build differs from the native one ({name}): {diff[:5]}"
print("PASS portable build: regress and native-equal stats")
PY
