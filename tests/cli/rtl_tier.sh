#!/usr/bin/env bash
# The rtl tier from the command line: the Verilated node L1 in the cycle tier. Both node L1s
# implement the node L1 timing spec v2 (rtl_model/README.md), so with 1, 32 and 128 rays in
# flight the image, every l1.* counter, the node DRAM bytes and the cycle count are the cycle
# tier's exactly. sim.vcd writes the RTL's port signals.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
common=(--set image.width=40 --set image.height=32 --set tracer.ray_order=wavefront)
for rif in 1 32 128; do
  "$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sim.tier=cycle --set sim.rays_in_flight=$rif --out "$tmp/c$rif" > /dev/null
  "$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sim.tier=rtl --set sim.rays_in_flight=$rif --out "$tmp/r$rif" > /dev/null
  cmp "$tmp/c$rif/image.png" "$tmp/r$rif/image.png"
done
python3 - "$tmp" <<'PY'
import json, sys
d = sys.argv[1]
for rif in [1, 32, 128]:
    c, r = (json.load(open(f"{d}/{n}{rif}/stats.json")) for n in ["c", "r"])
    assert r["sim.tier"] == "rtl" and c["rays.total"] == r["rays.total"]
    for k in ["l1.accesses", "l1.hits", "l1.misses", "l1.primary_misses", "l1.merged_misses",
              "l1.mshr_stall_cycles", "l1.mean_miss_latency_cycles", "dram.bytes.nodes",
              "dram.bytes.total", "sim.cycles"]:
        assert c[k] == r[k], (rif, k, c[k], r[k])
PY
# Fills known more than the unit queue's wheel (4096 cycles) ahead: a 6 us DRAM. Rays merged
# on one line then get their data in one cycle, some told long before (kept far ahead), some
# just before; their steps are booked in slot order either way, so the two L1s still agree.
slow=(--set dram.backend=fixed --set dram.latency_ns=6000 --set sim.rays_in_flight=32 --set image.png=false --set image.heatmaps=false)
"$rtusim" run "$src/configs/default.toml" "${common[@]}" "${slow[@]}" --set sim.tier=cycle --out "$tmp/cs" > /dev/null
"$rtusim" run "$src/configs/default.toml" "${common[@]}" "${slow[@]}" --set sim.tier=rtl --out "$tmp/rs" > /dev/null
python3 - "$tmp" <<'PY'
import json, sys
d = sys.argv[1]
c, r = (json.load(open(f"{d}/{n}/stats.json")) for n in ["cs", "rs"])
for k in ["l1.misses", "l1.primary_misses", "l1.merged_misses", "dram.bytes.nodes", "sim.cycles"]:
    assert c[k] == r[k], ("slow DRAM", k, c[k], r[k])
PY
# A DRAM faster than a unit cycle (a 5 MHz clock) with the data cache on: DRAM decides between
# edges and tells a fill for the next edge while the RTL's clock stands still; the clock then
# starts in the cycle under way (it used to stop the run: "came too late").
fast=(--set sim.clock_mhz=5 --set dcache.enable=true --set sim.rays_in_flight=128 --set image.png=false --set image.heatmaps=false)
"$rtusim" run "$src/configs/default.toml" "${common[@]}" "${fast[@]}" --set sim.tier=cycle --out "$tmp/cf" > /dev/null
"$rtusim" run "$src/configs/default.toml" "${common[@]}" "${fast[@]}" --set sim.tier=rtl --out "$tmp/rf" > /dev/null
"$rtusim" run "$src/configs/default.toml" "${common[@]}" "${fast[@]}" --set sim.tier=rtl --set sim.vcd="$tmp/f.vcd" --out "$tmp/rfv" > /dev/null
python3 - "$tmp" <<'PY'
import json, sys
d = sys.argv[1]
c, r, v = (json.load(open(f"{d}/{n}/stats.json")) for n in ["cf", "rf", "rfv"])
for k in ["l1.misses", "l1.primary_misses", "l1.merged_misses", "l1.mshr_stall_cycles",
          "dram.bytes.nodes", "dram.bytes.total", "sim.cycles"]:
    assert c[k] == r[k] == v[k], ("fast DRAM", k, c[k], r[k], v[k])
PY
# sim.vcd: the RTL L1's port signals, moved into place when the run has succeeded (no temporary
# file left beside it).
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sim.tier=rtl --set sim.vcd="$tmp/l1.vcd" --out "$tmp/v" > /dev/null
grep -q "o_fill_mshr" "$tmp/l1.vcd"
[ -z "$(find "$tmp" -maxdepth 1 -name 'l1.vcd?*')" ]
# An unbuilt RTL configuration is bad input naming it.
set +e
msg=$("$rtusim" run "$src/configs/default.toml" --set sim.tier=rtl --set l1.size=2048 --out "$tmp/bad" 2>&1 >/dev/null)
rc=$?
set -e
# Each check on its own line: under set -e a failing `a && b` list does not stop the script.
if [ $rc -ne 2 ]; then echo "FAIL: unbuilt RTL config exit $rc, want 2"; exit 1; fi
if ! grep -q "no RTL build for l1.size=2048" <<<"$msg"; then echo "FAIL: message: $msg"; exit 1; fi
if [ -e "$tmp/bad" ]; then echo "FAIL: output left in $tmp/bad"; exit 1; fi
echo "rtl_tier: 1 passed, 0 failed"
