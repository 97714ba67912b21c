#!/usr/bin/env bash
# The rtl tier from the command line: the Verilated node L1 in the cycle tier. Same hits as the
# cycle tier; with one ray in flight the same misses and node bytes, and cycles = the C++ L1's +
# 2 per primary miss (the RTL answers a miss two cycles later: fill edge + drain, see
# rtl_model/README.md); with 32 in flight within the documented bounds.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
common=(--set image.width=40 --set image.height=32 --set tracer.ray_order=wavefront)
for rif in 1 32; do
  "$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sim.tier=cycle --set sim.rays_in_flight=$rif --out "$tmp/c$rif" > /dev/null
  "$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sim.tier=rtl --set sim.rays_in_flight=$rif --out "$tmp/r$rif" > /dev/null
  cmp "$tmp/c$rif/image.png" "$tmp/r$rif/image.png"
done
python3 - "$tmp" <<'PY'
import json, sys
d = sys.argv[1]
c1, r1, c32, r32 = (json.load(open(f"{d}/{n}/stats.json")) for n in ["c1", "r1", "c32", "r32"])
assert r1["sim.tier"] == "rtl" and c1["rays.total"] == r1["rays.total"]
for k in ["l1.accesses", "l1.misses", "l1.primary_misses", "dram.bytes.nodes", "dram.bytes.total"]:
    assert c1[k] == r1[k], (k, c1[k], r1[k])
assert r1["sim.cycles"] == c1["sim.cycles"] + 2 * c1["l1.primary_misses"], (c1["sim.cycles"], r1["sim.cycles"])
rel = lambda a, b: abs(a - b) / b
assert rel(r32["l1.misses"], c32["l1.misses"]) <= 0.15
assert rel(r32["dram.bytes.nodes"], c32["dram.bytes.nodes"]) <= 0.06
assert rel(r32["sim.cycles"], c32["sim.cycles"]) <= 0.10
PY
# An unbuilt RTL configuration is bad input naming it.
set +e
msg=$("$rtusim" run "$src/configs/default.toml" --set sim.tier=rtl --set l1.size=2048 --out "$tmp/bad" 2>&1 >/dev/null)
rc=$?
set -e
[ $rc -eq 2 ] && grep -q "no RTL build for l1.size=2048" <<<"$msg" && [ ! -e "$tmp/bad" ]
echo "rtl_tier: 1 passed, 0 failed"
