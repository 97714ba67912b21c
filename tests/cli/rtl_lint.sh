#!/usr/bin/env bash
# `verilator --lint-only -Wall` over rtl_model/: every .sv at its defaults, and l1_cache.sv at
# each built parameter combination and a few corner cases, must be warning-free.
set -uo pipefail
src=$2
rtl="$src/rtl_model"
command -v verilator > /dev/null || { echo "rtl_lint: verilator not found"; echo "rtl_lint: 0 passed, 1 failed"; exit 1; }
pass=0; fail=0
lint() {  # lint NAME ARGS...
  local name=$1; shift
  if out=$(verilator --lint-only -Wall "$@" 2>&1); then
    pass=$((pass + 1))
  else
    fail=$((fail + 1)); echo "FAIL: $name"; echo "$out"
  fi
}
for sv in "$rtl"/*.sv; do lint "$(basename "$sv") (defaults)" "$sv"; done
l1="$rtl/l1_cache.sv"
# The built combinations (rtl_model/CMakeLists.txt RTUSIM_RTL_L1_BUILDS) and corner cases.
for g in "8192 4 64 0" "8192 4 64 1" "4096 2 32 1" "16384 8 64 0"; do
  read -r size ways line pol <<< "$g"
  lint "l1_cache $size/$ways/$line/policy=$pol" -GSIZE_BYTES="$size" -GWAYS="$ways" \
    -GLINE_BYTES="$line" -GPOLICY="$pol" "$l1"
done
lint "l1_cache hit latency 3, 3 MSHRs" -GHIT_LATENCY=3 -GMSHRS=3 "$l1"
lint "l1_cache 2 MSHRs, 2 sets, 32-bit addresses" -GMSHRS=2 -GSIZE_BYTES=512 -GADDR_W=32 "$l1"
# A bad parameter set must be rejected at elaboration.
if verilator --lint-only -Wall -GSIZE_BYTES=8000 "$l1" > /dev/null 2>&1; then
  fail=$((fail + 1)); echo "FAIL: SIZE_BYTES=8000 was not rejected"
else
  pass=$((pass + 1))
fi
echo "rtl_lint: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
