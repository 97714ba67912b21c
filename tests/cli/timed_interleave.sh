#!/usr/bin/env bash
# The timed interleaved functional mode (functional.timed): with one ray in flight its caches
# see the functional tier's stream (same DRAM bytes, same image); with 32 it is deterministic
# and the same at 1 and 2 threads, traces the same rays (same fetches, same image) in another
# order than round-robin, and reports estimate.cycles, which with one ray in flight is the cycle
# tier's sim.cycles to within the model's simplifications. In runs (functional.timed_segments)
# its figures are the same at 1, 2 and 7 threads, close to one model's, with the same image.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
w=(--set image.width=48 --set image.height=40 --set tracer.ray_order=wavefront --set image.heatmaps=false)
run() { local out=$1; shift; "$rtusim" run "$src/configs/default.toml" "${w[@]}" "$@" --out "$tmp/$out" > /dev/null; }
run f
run t1 --set functional.timed=true
run c1 --set sim.tier=cycle --set sim.rays_in_flight=1
run rr32 --set functional.rays_in_flight=32
run t32 --set functional.timed=true --set functional.rays_in_flight=32 --threads 1
run t32b --set functional.timed=true --set functional.rays_in_flight=32 --threads 2
run t32c --set functional.timed=true --set functional.rays_in_flight=32 --threads 2
run t8 --set functional.timed=true --set functional.rays_in_flight=8
seg=(--set functional.timed=true --set functional.rays_in_flight=8 --set functional.timed_segments=3 --set functional.timed_warmup_rays=32)
run s1 "${seg[@]}" --threads 1
run s2 "${seg[@]}" --threads 2
run s7 "${seg[@]}" --threads 7
cmp "$tmp/f/image.png" "$tmp/s2/image.png"
cmp "$tmp/f/image.png" "$tmp/t1/image.png"
cmp "$tmp/f/image.png" "$tmp/t32/image.png"
python3 - "$tmp" <<'PY'
import json, sys
d = sys.argv[1]
s = {k: json.load(open(f"{d}/{k}/stats.json"))
     for k in ["f", "t1", "c1", "rr32", "t32", "t32b", "t32c", "t8", "s1", "s2", "s7"]}
for k in ["dram.bytes.nodes", "dram.bytes.lists", "dram.bytes.triangles", "l1.misses", "traversal.node_fetches"]:
    assert s["t1"][k] == s["f"][k], (k, s["t1"][k], s["f"][k])
assert s["t1"]["dram.bytes.nodes"] == s["c1"]["dram.bytes.nodes"]
err = s["t1"]["estimate.cycles"] / s["c1"]["sim.cycles"] - 1
assert abs(err) < 0.05, f"one ray in flight: estimate.cycles {s['t1']['estimate.cycles']} vs sim.cycles {s['c1']['sim.cycles']}"
assert s["t32"]["traversal.node_fetches"] == s["f"]["traversal.node_fetches"]
assert s["t32"]["dram.bytes.nodes"] != s["rr32"]["dram.bytes.nodes"], "timed turns are not round-robin"
assert s["t32"]["estimate.cycles"] < s["t1"]["estimate.cycles"], "32 rays in flight overlap their waits"
assert s["t32"]["functional.timed"] is True and "functional.timed" not in s["rr32"]
def results(x):
    return {k: v for k, v in x.items() if "seconds" not in k and "per_second" not in k and k != "run.threads"}
assert results(s["t32"]) == results(s["t32b"]) == results(s["t32c"])
assert results(s["s1"]) == results(s["s2"]) == results(s["s7"])
# 1920 primary rays in 3 runs of >= 256 (8 x 32 warming rays); the shadow rays too.
assert s["s1"]["estimate.runs"] >= 7 and "estimate.runs" not in s["t8"], s["s1"]["estimate.runs"]
for k in ["traversal.node_fetches", "dram.bytes.nodes", "estimate.cycles"]:
    assert abs(s["s1"][k] / s["t8"][k] - 1) < 0.01, (k, s["s1"][k], s["t8"][k])
# Fetch counts are the traversal's, exactly, in runs too (they were the windows' sums).
for k in ["traversal.node_fetches", "traversal.list_fetches", "traversal.triangle_fetches",
          "fetch.nodes.fetches", "fetch.triangles.fetches"]:
    assert s["s1"][k] == s["f"][k], (k, s["s1"][k], s["f"][k])
PY
# A direct-mapped L1: a line's tags are often lost while its read is outstanding, and the next
# miss on it merges into that read: DRAM reads it once, as in the unit's L1 (node bytes =
# primary misses x line, near the cycle tier's; they were +7.7% off on Kitchen 128^2).
dm=(--set l1.assoc=1 --set sim.rays_in_flight=32 --set functional.rays_in_flight=32)
run dmc "${dm[@]}" --set sim.tier=cycle
run dmt "${dm[@]}" --set functional.timed=true
run dms "${dm[@]}" --set functional.timed=true --set functional.timed_segments=3 --set functional.timed_warmup_rays=128
python3 - "$tmp" <<'PY'
import json, sys
d = sys.argv[1]
c, t, s = (json.load(open(f"{d}/{n}/stats.json")) for n in ["dmc", "dmt", "dms"])
for x in (t, s):
    assert x["dram.bytes.nodes"] == 64 * x["estimate.l1.primary_misses"], x["dram.bytes.nodes"]
    assert x["fetch.nodes.misses"] > x["estimate.l1.primary_misses"], "no merge lost its tags: no test"
assert c["dram.bytes.nodes"] == 64 * c["l1.primary_misses"]
err = t["dram.bytes.nodes"] / c["dram.bytes.nodes"] - 1
assert abs(err) < 0.01, f"direct-mapped: timed node bytes {err:+.2%} off the cycle tier's"
PY
echo PASS
