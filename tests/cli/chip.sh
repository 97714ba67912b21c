#!/usr/bin/env bash
# The chip in the functional tier (chip.units, l2.*), checked against independent truths:
# - the L2's input stream (`rtusim trace --level l2`) through the Python reference cache
#   (tests/cache_ref.py) gives exactly l2.accesses and l2.misses, for 1 and 4 units;
# - with one unit (in the tracer's order), the node requests in that stream are the node L1's
#   misses that a plain Python LRU computes from the node-fetch trace, line by line in order;
# - an L2 changes nothing before it (l1.*, traversal.*), and what the L1s send it is what they
#   sent DRAM without it; the units' counts add up to the totals and to the one-unit fetches;
# - the same stats for --threads 1 and 2; sweep points over chip.units and l2.* equal their runs
#   (an LRU L2's sizes and ways in one pass); a chip where it is not modelled, and --level l2
#   misused, exit 2 with one line.
set -uo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
py=${RTUSIM_PYTHON:-python3}
pass=0; fail=0
ok() { pass=$((pass+1)); }
bad() { echo "FAIL $*"; fail=$((fail+1)); }
cfg=$src/configs/default.toml
small=(--set image.width=48 --set image.height=48 --set image.png=false --set image.heatmaps=false)
l2=(--set l2.enable=true --set l2.size=16384 --set l2.assoc=4 --set l2.line=64)
key() { "$py" -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }

run() {  # run NAME ARGS...: rtusim run into $tmp/NAME
  local name=$1; shift
  "$rtusim" run "$cfg" "${small[@]}" "$@" --out "$tmp/$name" > /dev/null || bad "run $name"
}
run plain
# One unit takes the tracer's own order in runs of rays (tiles would trace tile by tile).
run l2u1 "${l2[@]}" --set chip.distribution=batches
run l2u4 "${l2[@]}" --set chip.units=4
run l2u4t1 "${l2[@]}" --set chip.units=4 --threads 1
run u4 --set chip.units=4
run l2u4b "${l2[@]}" --set chip.units=4 --set chip.distribution=batches --set chip.batch_rays=16 \
  --set tracer.ray_order=wavefront --set dcache.enable=true

# 1. The L2 against the Python reference, 1 and 4 units, both distributions.
for case in "l2u1 1 batches recursive false" "l2u4 4 tiles recursive false" \
            "l2u4b 4 batches wavefront true"; do
  read -r name units dist order dcache <<< "$case"
  "$rtusim" trace "$cfg" "${small[@]}" "${l2[@]}" --set chip.units=$units \
    --set chip.distribution=$dist --set chip.batch_rays=16 --set tracer.ray_order=$order \
    --set dcache.enable=$dcache --level l2 --out "$tmp/$name.din" > /dev/null || bad "trace --level l2 $name"
  want_misses=$("$py" "$src/tests/cache_ref.py" "$tmp/$name.din" 16384 4 64 lru | awk '{print $2}')
  want_accesses=$(grep -c . "$tmp/$name.din")
  got_misses=$(key "$tmp/$name/stats.json" l2.misses)
  got_accesses=$(key "$tmp/$name/stats.json" l2.accesses)
  [ "$got_misses" = "$want_misses" ] && [ "$got_accesses" = "$want_accesses" ] && ok ||
    bad "$name: l2.misses $got_misses / accesses $got_accesses, reference $want_misses / $want_accesses"
done

# 2. One unit: the node requests the L2 takes are the node L1's LRU misses, in order, in the
# tracer's order (batches) and tile by tile (tiles; trace writes the node stream in that order).
"$rtusim" trace "$cfg" "${small[@]}" --out "$tmp/nodes.din" > /dev/null || bad "trace nodes"
"$rtusim" trace "$cfg" "${small[@]}" "${l2[@]}" --out "$tmp/nodes_tiles.din" > /dev/null ||
  bad "trace nodes, tiles"
"$rtusim" trace "$cfg" "${small[@]}" "${l2[@]}" --level l2 --out "$tmp/l2u1_tiles.din" > /dev/null ||
  bad "trace --level l2, tiles"
cmp -s "$tmp/nodes.din" "$tmp/nodes_tiles.din" && bad "tile order is the scan order"
for pair in "nodes l2u1" "nodes_tiles l2u1_tiles"; do
  read -r nodes l2in <<< "$pair"
  "$py" - "$tmp/$nodes.din" "$tmp/$l2in.din" "$(key "$tmp/plain/stats.json" mem.nodes.bytes)" <<'PY' && ok || bad "one unit ($l2in): node requests are not the L1's misses"
import sys
from collections import OrderedDict
nodes = [int(l.split()[1], 16) for l in open(sys.argv[1]) if l.strip()]
l2_in = [int(l.split()[1], 16) for l in open(sys.argv[2]) if l.strip()]
node_end = int(sys.argv[3])  # the node region comes first, at address 0
sets = [OrderedDict() for _ in range(8192 // (64 * 4))]
misses = []
for a in nodes:  # 8-byte nodes, 8-byte aligned: one line each
    line = a // 64
    s = sets[line % len(sets)]
    if line in s:
        s.move_to_end(line)
        continue
    misses.append(line * 64)
    s[line] = True
    if len(s) > 4:
        s.popitem(last=False)
node_requests = [a for a in l2_in if a < node_end]
assert misses == node_requests, (len(misses), len(node_requests))
PY
done

# 3. Before the L2 nothing changes; the L1s send the L2 what they sent DRAM; sums and threads.
"$py" - "$tmp" <<'PY' && ok || bad "level and unit sums"
import json, sys
d = sys.argv[1]
s = {n: json.load(open(f"{d}/{n}/stats.json")) for n in ["plain", "l2u1", "l2u4", "l2u4t1", "u4"]}
timing = lambda k: k.endswith(("seconds", "trace.rays_per_second"))
for k, v in s["plain"].items():
    if k.startswith(("l1.", "traversal.", "fetch.", "rays.")):
        assert s["l2u1"][k] == v, k
assert s["l2u1"]["l2.bytes.in"] == s["plain"]["dram.bytes.total"]
assert s["l2u1"]["l2.misses"] * 64 == s["l2u1"]["dram.bytes.total"]
for n in ["l2u4", "u4"]:
    t = s[n]
    assert t["traversal.node_fetches"] == s["plain"]["traversal.node_fetches"], n
    for k in ["l1.accesses", "l1.misses", "traversal.node_fetches", "rays.total"]:
        total = t[k]
        assert sum(t[f"units.{u}.{k}"] for u in range(4)) == total, (n, k)
    assert all(t[f"units.{u}.rays.total"] > 0 for u in range(4)), n
t = s["u4"]
assert sum(t[f"units.{u}.dram.bytes.total"] for u in range(4)) == t["dram.bytes.total"]
t = s["l2u4"]
assert t["l2.bytes.in"] == s["u4"]["dram.bytes.total"]  # same units, same L1s
assert sum(t[f"units.{u}.l2.misses"] for u in range(4)) == t["l2.misses"]
assert t["l2.hits"] + t["l2.misses"] == t["l2.accesses"] and t["l2.hits"] > 0
a, b = s["l2u4"], s["l2u4t1"]
assert {k for k in a if not timing(k)} == {k for k in b if not timing(k)}
assert all(a[k] == b[k] for k in a if not timing(k)), [k for k in a if not timing(k) and a[k] != b[k]]
PY

# 4. Sweep points equal their runs: chip.units and l2.size; and an L1 x L2 product whose LRU L2s
# (every size and ways, "full" included) come from one pass per L1 point, both distributions,
# beside a tree-PLRU L2 that runs alone.
cat > "$tmp/sweep.toml" <<'TOML'
[image]
width = 32
height = 32
png = false
[l2]
enable = true
[sweep]
chip.units = [1, 4]
l2.size = [16384, 65536]
TOML
"$rtusim" sweep "$tmp/sweep.toml" --out "$tmp/sweep" --no-plots > /dev/null || bad "chip sweep"
"$py" "$src/tests/cli/sweep_check.py" "$rtusim" "$tmp/sweep" 1 chip.units,l2.size && ok ||
  bad "chip sweep differs from rtusim run"
cat > "$tmp/l2sweep.toml" <<'TOML'
[image]
width = 32
height = 32
png = false
[tracer]
ray_order = "wavefront"
[chip]
units = 3
[l2]
enable = true
line = 128
[sweep]
layout.kind = ["dfl", "odfl"]
l1.size = [2048, 8192]
l2.size = [8192, 65536]
l2.assoc = [1, 4, "full"]
l2.policy = ["lru", "tree-plru"]
chip.distribution = ["tiles", "batches"]
TOML
"$rtusim" sweep "$tmp/l2sweep.toml" --out "$tmp/l2sweep" --no-plots > /dev/null || bad "L2 sweep"
# Jobs: per distribution and L1 point one LRU family (12 points); each tree-PLRU point alone.
"$py" - "$tmp/l2sweep/timings.csv" <<'PY' && ok || bad "L2 sweep: not one job per LRU family"
import csv, sys
jobs = list(csv.DictReader(open(sys.argv[1])))
families = [j for j in jobs if j["alone"] == "0"]
assert len(families) == 4 and all(j["points"] == "12" for j in families), jobs
assert sum(j["alone"] == "1" for j in jobs) == 48, len(jobs)
PY
cols=$(head -1 "$tmp/l2sweep/results.csv" | cut -d, -f1-6)
"$py" "$src/tests/cli/sweep_check.py" "$rtusim" "$tmp/l2sweep" 3 "$cols" && ok ||
  bad "L2 sweep differs from rtusim run"

# 5. scripts/chip_table.py: its table holds the runs' figures (the built-in room, 32x32).
if [ -x "$src/.venv/bin/python" ]; then
  "$src/.venv/bin/python" "$src/scripts/chip_table.py" --scenes default --size 32 --units 1 3 \
    --out "$tmp/ct" --rtusim "$rtusim" > /dev/null || bad "chip_table.py"
  "$py" - "$tmp/ct" <<'PY' && ok || bad "chip_table.py: the CSV is not the runs' stats"
import csv, json, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(f"{d}/chip_layouts.csv")))
assert len(rows) == 3 * 5, len(rows)  # no L2, 1 and 3 units; five layouts
for r in rows:
    name = "default_no_l2" if r["units"] == "0" else f"default_{r['units']}_units"
    s = json.load(open(f"{d}/{name}/stats.json"))
    p = f"layout.{r['layout']}."
    assert int(r["dram_node_bytes"]) == s[p + "dram.bytes.nodes"], r
    if r["units"] != "0":
        assert int(r["l2_in_node_bytes"]) == s[p + "l2.bytes.in.nodes"], r
        assert s["chip.units"] == int(r["units"]), r
table = open(f"{d}/chip_layouts.md").read()
assert "| default | odfl |" in table and "3 units: L1→L2 MB" in table
PY
fi

# 6. Bad input: one line, exit 2, nothing written.
expect_refusal() {  # expect_refusal WORD ARGS...: exit 2, one line naming WORD, no output
  local word=$1; shift
  "$rtusim" "$@" > /dev/null 2> "$tmp/err"; local rc=$?
  if [ $rc -eq 2 ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -q -- "$word" "$tmp/err" &&
     [ ! -e "$tmp/refused" ]; then ok; else bad "refusal $word (rc $rc): $(cat "$tmp/err")"; fi
}
expect_refusal chip.units run "$cfg" --set chip.units=4 --set sim.tier=cycle --out "$tmp/refused"
expect_refusal l2.enable run "$cfg" --set l2.enable=true --set functional.rays_in_flight=8 --out "$tmp/refused"
expect_refusal chip.units run "$cfg" --set chip.units=2 --set sample.rate=0.5 --out "$tmp/refused"
expect_refusal l2.enable trace "$cfg" --level l2 --out "$tmp/refused"
expect_refusal "level l2" trace "$cfg" "${l2[@]}" --level l2 --format bin --out "$tmp/refused"
expect_refusal chip.units trace "$cfg" --set chip.units=2 --out "$tmp/refused"
expect_refusal chip.distribution run "$cfg" --set chip.distribution=rows --out "$tmp/refused"

echo "chip: $pass passed, $fail failed"
[ $fail -eq 0 ]
