#!/usr/bin/env bash
# Sampled runs end to end: every extensive figure gets a whole-frame estimate whose 95% CI holds
# the full run's figure and is not wide, the paired ODFL-DFL difference has its own CI, which
# holds the full run's difference, excludes 0 and is far narrower than the unpaired one, too few
# units is said on stderr and in the stats, bad sample keys are input errors; the interleaved mode with one ray in flight is the
# functional tier, and with 32 in wavefront order it moves different node bytes.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
common=(--set image.width=64 --set image.height=64 --set 'layout.kind=["dfl","odfl"]')
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sample.rate=0.5 --set sample.unit_pixels=8 \
  --out "$tmp/s" > /dev/null 2> "$tmp/s.err"
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sample.rate=0.02 --out "$tmp/few" > /dev/null 2> "$tmp/few.err"
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --out "$tmp/full" > /dev/null
grep -q "sample: .* units < sample.min_units = 30: the 95% confidence intervals are not valid" "$tmp/few.err"
[ ! -s "$tmp/s.err" ]
python3 - "$tmp/s/stats.json" "$tmp/few/stats.json" "$tmp/full/stats.json" <<'PY'
import json, math, sys
s, few, full = (json.load(open(p)) for p in sys.argv[1:4])
# Half the frame (seed 1): each CI holds the full run's figure, its half-width within 30% of it
# (19% for node bytes: the mirror and the glass sphere make a heavy tail).
for k in ["rays.total", "dram.bytes.nodes", "dram.bytes.total", "l1.misses", "layout.odfl.dram.bytes.nodes"]:
    assert s[k + ".ci95_low"] <= full[k] <= s[k + ".ci95_high"], (k, s[k + ".ci95_low"], full[k], s[k + ".ci95_high"])
    assert s[k + ".ci95_high"] - s[k] < 0.3 * full[k], (k, s[k], s[k + ".ci95_high"])
d = "sample.diff.odfl-dfl.dram.bytes.nodes"
assert abs(s[d] - (s["layout.odfl.dram.bytes.nodes"] - s["layout.dfl.dram.bytes.nodes"])) < 1e-6 * s["dram.bytes.nodes"]
# The paired CI holds the full run's difference and not 0 (ODFL moves fewer node bytes), and is
# far narrower than the unpaired sqrt(hw_dfl^2 + hw_odfl^2).
true_d = full["layout.odfl.dram.bytes.nodes"] - full["layout.dfl.dram.bytes.nodes"]
assert s[d + ".ci95_low"] <= true_d <= s[d + ".ci95_high"], (s[d + ".ci95_low"], true_d, s[d + ".ci95_high"])
assert s[d + ".ci95_high"] < 0, (d, s[d + ".ci95_high"])
hw = lambda k: s[k + ".ci95_high"] - s[k]
unpaired = math.hypot(hw("layout.dfl.dram.bytes.nodes"), hw("layout.odfl.dram.bytes.nodes"))
assert hw(d) < unpaired / 2, (hw(d), unpaired)
assert s["sample.units"] == 256 and s["sample.units_total"] == 512 and s["sample.ci_valid"] is True
assert abs(s["sample.fraction"] - 0.5) < 1e-9
assert few["sample.ci_valid"] is False and "min_units" in few["sample.problem"]
PY
# Wavefront order: the whole frame is traced per generation (its image and ray counts are the full
# run's) and only the drawn units' rays are measured; nothing to warn about. Seed 2: seed 1's
# paired CI is one of the 1 in 20 that miss (by 2%; 28 of seeds 1-30 hold the difference).
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --set tracer.ray_order=wavefront --out "$tmp/wffull" > /dev/null
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sample.rate=0.5 --set tracer.ray_order=wavefront \
  --set sample.seed=2 --out "$tmp/wf" > /dev/null 2> "$tmp/wf.err"
[ ! -s "$tmp/wf.err" ]
cmp "$tmp/wffull/image.png" "$tmp/wf/image.png"
python3 - "$tmp/s/stats.json" "$tmp/wf/stats.json" "$tmp/wffull/stats.json" <<'PY'
import json, sys
s, wf, full = (json.load(open(p)) for p in sys.argv[1:4])
assert s["sample.per_generation"] is False and wf["sample.per_generation"] is True
for k in ["rays.total", "rays.shadow", "rays.reflection"]:
    assert wf[k] == wf[k + ".ci95_low"] == wf[k + ".ci95_high"] == full[k], k
for k in ["dram.bytes.nodes", "layout.odfl.dram.bytes.nodes"]:
    assert wf[k + ".ci95_low"] <= full[k] <= wf[k + ".ci95_high"], k
d = "sample.diff.odfl-dfl.dram.bytes.nodes"
true_d = full["layout.odfl.dram.bytes.nodes"] - full["layout.dfl.dram.bytes.nodes"]
assert wf[d + ".ci95_low"] <= true_d <= wf[d + ".ci95_high"] < 0, (wf[d + ".ci95_low"], true_d, wf[d + ".ci95_high"])
assert 0 < wf["sample.rays_simulated"] < full["rays.total"]
PY
# Every unit in one round: each batch goes through the tier whole, in the full run's order, so the
# units' sums are the full run's figures exactly (the per-generation units cover the frame).
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sample.rate=0.9999 --set tracer.ray_order=wavefront \
  --out "$tmp/wfall" > /dev/null
python3 - "$tmp/wfall/stats.json" "$tmp/wffull/stats.json" <<'PY'
import json, sys
a, full = (json.load(open(p)) for p in sys.argv[1:3])
assert a["sample.units"] == a["sample.units_total"] and a["sample.rays_warmed"] == 0
for k in ["dram.bytes.nodes", "dram.bytes.total", "l1.misses", "layout.odfl.dram.bytes.nodes"]:
    assert a[k] == full[k], (k, a[k], full[k])
PY
# The timed interleaved mode's estimate.* are extensive figures too: whole-frame estimates with
# CIs. Recursive order (one ray at a time): every unit gives the full run's figures exactly, and
# 20% of the frame's CI holds them. Wavefront order, one ray in flight: the same. With 32 in
# flight each unit's run of a batch starts empty and drains (the cut, docs/accuracy.md): every
# unit overestimates estimate.cycles by as much as the cycle tier's sampled sim.cycles (within 3
# points: the same cut of the same runs), and 20% stays of the full run's order.
t=(--set image.width=64 --set image.height=64 --set functional.timed=true --set image.png=false --set image.heatmaps=false)
trun() { local out=$1; shift; "$rtusim" run "$src/configs/default.toml" "${t[@]}" "$@" --out "$tmp/$out" > /dev/null; }
for o in recursive wavefront; do
  trun "tfull_$o" --set tracer.ray_order=$o
  trun "tall_$o" --set tracer.ray_order=$o --set sample.rate=0.9999
  trun "t20_$o" --set tracer.ray_order=$o --set sample.rate=0.2 --set sample.unit_pixels=16
done
trun tfull32 --set tracer.ray_order=wavefront --set functional.rays_in_flight=32
trun tall32 --set tracer.ray_order=wavefront --set functional.rays_in_flight=32 --set sample.rate=0.9999
trun t20_32 --set tracer.ray_order=wavefront --set functional.rays_in_flight=32 --set sample.rate=0.2 --set sample.unit_pixels=16
c=(--set tracer.ray_order=wavefront --set sim.tier=cycle --set sim.rays_in_flight=32)
trun cfull32 "${c[@]}"
trun call32 "${c[@]}" --set sample.rate=0.9999
python3 - "$tmp" <<'PY'
import json, sys
s = lambda k: json.load(open(f"{sys.argv[1]}/{k}/stats.json"))
keys = ["estimate.cycles", "estimate.l1.primary_misses", "estimate.l1.mshr_stall_cycles"]
for o in ["recursive", "wavefront"]:
    full, every, part = s(f"tfull_{o}"), s(f"tall_{o}"), s(f"t20_{o}")
    assert every["sample.units"] == every["sample.units_total"]
    for k in keys:
        assert abs(every[k] - full[k]) <= 1e-9 * full[k], (o, k, every[k], full[k])
    k = "estimate.cycles"
    assert part[k + ".ci95_low"] <= full[k] <= part[k + ".ci95_high"], (o, part[k], full[k])
    assert part["sample.units"] < part["sample.units_total"] / 4
full, every, part = s("tfull32"), s("tall32"), s("t20_32")
cut_timed = every["estimate.cycles"] / full["estimate.cycles"] - 1
cut_cycle = s("call32")["sim.cycles"] / s("cfull32")["sim.cycles"] - 1
assert cut_timed > 0.1 and abs(cut_timed - cut_cycle) < 0.03, (cut_timed, cut_cycle)
assert 0.5 < part["estimate.cycles"] / full["estimate.cycles"] < 2.0
PY
# The ratio estimator (wavefront order): node bytes per ray of the drawn units x the frame's rays;
# rays.* exact; the paired difference is the difference of the two estimates (same units, same
# rays); every unit gives the full run's figures. Seed 2 as above (seed 1's CIs, 15% high, miss the
# full run by 1%); the CIs hold the full run's figures and difference.
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sample.rate=0.5 --set tracer.ray_order=wavefront \
  --set sample.estimator=ratio --set sample.seed=2 --out "$tmp/wfr" > /dev/null
"$rtusim" run "$src/configs/default.toml" "${common[@]}" --set sample.rate=0.9999 --set tracer.ray_order=wavefront \
  --set sample.estimator=ratio --out "$tmp/wfrall" > /dev/null
python3 - "$tmp/wfr/stats.json" "$tmp/wfrall/stats.json" "$tmp/wffull/stats.json" "$tmp/wf/stats.json" <<'PY'
import json, sys
r, rall, full, mean = (json.load(open(p)) for p in sys.argv[1:5])
assert r["sample.estimator"] == "ratio" and mean["sample.estimator"] == "mean"
assert r["rays.total"] == full["rays.total"]
d = "sample.diff.odfl-dfl.dram.bytes.nodes"
assert abs(r[d] - (r["layout.odfl.dram.bytes.nodes"] - r["layout.dfl.dram.bytes.nodes"])) < 1e-6 * r["dram.bytes.nodes"]
for k in ["dram.bytes.nodes", "layout.odfl.dram.bytes.nodes"]:
    assert r[k + ".ci95_low"] <= full[k] <= r[k + ".ci95_high"], k
true_d = full["layout.odfl.dram.bytes.nodes"] - full["layout.dfl.dram.bytes.nodes"]
assert r[d + ".ci95_low"] <= true_d <= r[d + ".ci95_high"] < 0, (r[d + ".ci95_low"], true_d, r[d + ".ci95_high"])
assert r["dram.bytes.nodes"] != mean["dram.bytes.nodes"]
for k in ["dram.bytes.nodes", "l1.misses", "layout.odfl.dram.bytes.nodes"]:
    assert abs(rall[k] - full[k]) <= 1e-9 * full[k], (k, rall[k], full[k])
PY
# Bad sample keys: exit 2, one line naming the key, no output.
for bad in "sample.method=pixels" "sample.rate=0" "sample.warmup=detailed" "sample.target_key=tree.nodes" \
           "sample.estimator=median" "sample.estimator=ratio"; do
  set +e
  "$rtusim" run "$src/configs/default.toml" --set "$bad" --out "$tmp/bad" > /dev/null 2> "$tmp/bad.err"
  rc=$?
  set -e
  [ $rc -eq 2 ] && [ "$(wc -l < "$tmp/bad.err")" -eq 1 ] && grep -q "${bad%%=*}" "$tmp/bad.err" && [ ! -e "$tmp/bad/stats.json" ] \
    || { echo "FAIL $bad: exit $rc"; cat "$tmp/bad.err"; exit 1; }
done
# Few units with a heavy tail (single random pixels of an 8x8 frame): a count's interval stops
# at zero, a paired difference's may go below.
"$rtusim" run "$src/configs/default.toml" --set image.width=8 --set image.height=8 \
  --set sample.method=random --set sample.unit_pixels=1 --set sample.rate=0.3 \
  --set 'layout.kind=["dfl","odfl"]' --set image.png=false --out "$tmp/floor" > /dev/null 2>&1
python3 - "$tmp/floor/stats.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
lows = {k: v for k, v in s.items() if k.endswith(".ci95_low") and not k.startswith("sample.diff.")}
assert lows and min(lows.values()) >= 0, sorted(lows.items(), key=lambda kv: kv[1])[:3]
assert 0 in lows.values(), "no interval reached zero: the case no longer tests the floor"
PY
# Found by a helper's audit: a sampled cycle-tier run estimates its unit and DRAM counters too
# (they were the measured and warming rays' raw counts), and its rates from the estimates;
# rays.primary is known exactly in recursive order with units of unequal size; a wavefront
# target on an unknown rays.* key is refused; target rounds count the finite population.
c=(--set image.width=64 --set image.height=64)
"$rtusim" run "$src/configs/default.toml" "${c[@]}" --set sim.tier=cycle --set sample.rate=0.25 --out "$tmp/cyc" > /dev/null 2>&1
"$rtusim" run "$src/configs/default.toml" "${c[@]}" --set sample.method=random --set sample.unit_pixels=30 \
  --set sample.rate=0.3 --out "$tmp/uneq" > /dev/null 2>&1
"$rtusim" run "$src/configs/default.toml" --set image.width=128 --set image.height=128 --set 'layout.kind=["cluster"]' \
  --set sample.target_ci=0.2 --set sample.target_key=dram.bytes.nodes --out "$tmp/fpc" > /dev/null 2>&1
if "$rtusim" run "$src/configs/default.toml" "${c[@]}" --set tracer.ray_order=wavefront --set sample.target_ci=0.01 \
     --set sample.rate=0.5 --set 'sample.target_key="rays.bogus"' --out "$tmp/bogus" 2> "$tmp/bogus.err"; then
  echo "FAIL: target_key rays.bogus accepted"; exit 1
fi
grep -q "sample.target_key: 'rays.bogus'" "$tmp/bogus.err"; [ ! -e "$tmp/bogus" ]
"$rtusim" run "$src/configs/default.toml" "${c[@]}" --set sim.tier=cycle --out "$tmp/cycfull" > /dev/null 2>&1
python3 - "$tmp/cyc/stats.json" "$tmp/uneq/stats.json" "$tmp/fpc/stats.json" "$tmp/cycfull/stats.json" "$tmp/full/stats.json" <<'PY'
import json, sys
c, u, f, cfull, full = (json.load(open(p)) for p in sys.argv[1:6])
for k in ("unit.rays", "unit.steps", "unit.isect_tests", "dram.requests", "dram.row_hits"):
    assert c[k + ".ci95_low"] <= cfull[k] <= c[k + ".ci95_high"], (k, c[k + ".ci95_low"], cfull[k], c[k + ".ci95_high"])
# The unit's rays are the frame's rays (unit.rays was the raw count: 8338 against 13368).
assert abs(c["unit.rays"] / c["rays.total"] - 1) < 1e-9, (c["unit.rays"], c["rays.total"])
assert abs(c["unit.utilisation"] - c["unit.steps"] / c["sim.cycles"]) < 1e-12
rows = c["dram.row_hits"] + c["dram.row_misses"] + c["dram.row_conflicts"]
assert abs(c["dram.row_hit_rate"] - c["dram.row_hits"] / rows) < 1e-12
assert u["rays.primary"] == 64 * 64 == u["rays.primary.ci95_low"] == u["rays.primary.ci95_high"]
# rays.total is the pixels plus the other rays' estimate: it holds its kinds' sum.
kinds = sum(u[f"rays.{k}"] for k in ("primary", "shadow", "reflection", "refraction"))
assert abs(u["rays.total"] - kinds) < 1e-6 * kinds, (u["rays.total"], kinds)
assert u["rays.total.ci95_low"] <= full["rays.total"] <= u["rays.total.ci95_high"]
assert f["sample.units"] < 300, f"target rounds overshoot: {f['sample.units']} of 512 units for 0.2"
assert f["sample.target_met"] is True
PY
# Interleaved functional mode.
w=(--set image.width=48 --set image.height=40 --set tracer.ray_order=wavefront)
"$rtusim" run "$src/configs/default.toml" "${w[@]}" --out "$tmp/f" > /dev/null
"$rtusim" run "$src/configs/default.toml" "${w[@]}" --set functional.rays_in_flight=32 --out "$tmp/i32" > /dev/null
cmp "$tmp/f/image.png" "$tmp/i32/image.png"
python3 - "$tmp/f/stats.json" "$tmp/i32/stats.json" <<'PY'
import json, sys
f, i = (json.load(open(p)) for p in sys.argv[1:3])
assert f["traversal.node_fetches"] == i["traversal.node_fetches"]
assert f["dram.bytes.nodes"] != i["dram.bytes.nodes"], "32 rays in flight change the node stream"
assert i["functional.rays_in_flight"] == 32 and "functional.rays_in_flight" not in f
PY
echo PASS
