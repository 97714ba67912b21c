#!/usr/bin/env bash
# The tiers agree: the cycle tier traces the same rays to the same hits (identical image and ray
# counts) as the functional tier, and with one ray in flight in wavefront order it moves exactly
# the functional tier's node bytes; more rays in flight take fewer cycles.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
common=(--set image.width=48 --set image.height=40 --set tracer.ray_order=wavefront
        --set 'layout.kind=["dfl","odfl"]')
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --out "$tmp/f" > /dev/null
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sim.tier=cycle --set sim.rays_in_flight=1 --out "$tmp/c1" > /dev/null
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sim.tier=cycle --set sim.rays_in_flight=32 --out "$tmp/c32" > /dev/null
cmp "$tmp/f/image.png" "$tmp/c1/image.png"
cmp "$tmp/f/image.png" "$tmp/c32/image.png"
python3 - "$tmp/f/stats.json" "$tmp/c1/stats.json" "$tmp/c32/stats.json" <<'PY'
import json, sys
f, c1, c32 = (json.load(open(p)) for p in sys.argv[1:4])
for k in ["rays.total", "rays.primary", "rays.shadow", "rays.reflection", "rays.refraction"]:
    assert f[k] == c1[k] == c32[k], k
for kind in ["dfl", "odfl"]:
    p = f"layout.{kind}."
    # Same node visits (the same step function over the same rays).
    assert f[p + "traversal.node_fetches"] == c1[p + "traversal.node_fetches"] == c32[p + "traversal.node_fetches"]
    # One ray in flight: the functional tier's exact node stream, so its exact bytes and misses.
    assert f[p + "dram.bytes.nodes"] == c1[p + "dram.bytes.nodes"], (kind, f[p + "dram.bytes.nodes"], c1[p + "dram.bytes.nodes"])
    assert f[p + "l1.misses"] == c1[p + "l1.misses"]
    assert c1[p + "l1.merged_misses"] == 0
    # More rays in flight hide latency.
    assert c32[p + "sim.cycles"] * 2 < c1[p + "sim.cycles"], (c1[p + "sim.cycles"], c32[p + "sim.cycles"])
assert "sim.cycles" not in f and c1["sim.cycles"] > 0
PY
# A DRAM burst other than 64 bytes (4-byte bus x 4): lists and triangles straight from DRAM cost
# that burst in every tier (the functional tier read 64-byte bursts whatever the config said:
# +37% total bytes at 4-byte buses); a sweep point over dram.* equals its single run.
b=(--set image.width=24 --set image.height=24 --set dram.bus_bytes=4 --set dram.burst_length=4)
"$rtusim" run "$src/configs/default.toml" "${b[@]}" --out "$tmp/bf" > /dev/null
"$rtusim" run "$src/configs/default.toml" "${b[@]}" --set sim.tier=cycle --set sim.rays_in_flight=1 --out "$tmp/bc" > /dev/null
printf '[image]\nwidth = 24\nheight = 24\n[dram]\nburst_length = 4\n[sweep]\n"dram.bus_bytes" = [4, 8]\n' > "$tmp/b.toml"
"$rtusim" sweep "$tmp/b.toml" --out "$tmp/bs" --no-plots > /dev/null 2>&1
python3 - "$tmp/bf/stats.json" "$tmp/bc/stats.json" "$tmp/bs/results.csv" <<'PY'
import csv, json, sys
f, c = (json.load(open(p)) for p in sys.argv[1:3])
for k in ["dram.bytes.nodes", "dram.bytes.lists", "dram.bytes.triangles", "dram.bytes.total"]:
    assert f[k] == c[k], (k, f[k], c[k])
row = next(r for r in csv.DictReader(open(sys.argv[3])) if r["dram.bus_bytes"] == "4")
assert float(row["dram.bytes.triangles"]) == f["dram.bytes.triangles"], (row["dram.bytes.triangles"], f["dram.bytes.triangles"])
PY
# backend fixed: its latency defaults to a row miss of the timings in effect (it kept the
# preset's 28.32 ns when tRCD and tCL were set).
"$rtusim" run "$src/configs/default.toml" --set image.width=8 --set image.height=8 --set dram.backend=fixed \
  --set dram.tRCD_ns=50 --set dram.tCL_ns=50 --out "$tmp/fx" > /dev/null
grep -qx 'latency_ns = 100.0' "$tmp/fx/config.toml" || { echo "FAIL: fixed latency not tRCD + tCL"; exit 1; }
# sim.vcd: the unit's state over its own cycle times, one file per layout.
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sim.tier=cycle --set sim.vcd="$tmp/unit.vcd" --out "$tmp/v" > /dev/null
python3 - "$tmp/unit_dfl.vcd" "$tmp/unit_odfl.vcd" "$tmp/c32/stats.json" <<'PY'
import json, sys
stats = json.load(open(sys.argv[3]))
for path in sys.argv[1:3]:
    text = open(path).read()
    assert "$var wire 32 ! rays_active $end" in text and "$enddefinitions $end" in text
    times = [int(l[1:]) for l in text.splitlines() if l.startswith("#")]
    assert len(times) > 10 and times == sorted(times), "times increase"
    # The last value of `steps` is the run's step count (32 rays in flight is the default).
    last_steps = [l for l in text.splitlines() if l.endswith(' "')][-1]
    kind = path.rsplit("_", 1)[1].removesuffix(".vcd")  # unit_<kind>.vcd ("dfl" is in "odfl")
    assert kind in ("dfl", "odfl"), path
    assert int(last_steps[1:].split()[0], 2) == stats[f"layout.{kind}.traversal.node_fetches"]
PY
echo "tier_consistency: 1 passed, 0 failed"
