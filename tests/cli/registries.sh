#!/usr/bin/env bash
# Every registered name of every seam, end to end: each layout, replacement policy, DRAM
# backend and tier that `rtusim keys` lists as a choice runs a small frame; hits (rays) agree
# within a tier, the tier's keys are there, and the DRAM backends give different timings.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
small=(--set image.width=16 --set image.height=12 --set image.png=false --set image.heatmaps=false)

"$rtusim" keys --format json > "$tmp/keys.json"
choices() {  # the registered names of a key, from `rtusim keys`
  python3 -c "import json,sys; k={x['key']:x for x in json.load(open(sys.argv[1]))}[sys.argv[2]]; \
assert k['range'].startswith('one of: '), k; print(' '.join(k['range'][8:].split(', ')))" "$tmp/keys.json" "$1"
}
run() {  # run NAME --set ...
  local name=$1; shift
  "$rtusim" run "$src/configs/default.toml" "${small[@]}" "$@" --out "$tmp/$name" > "$tmp/$name.log" \
    || { echo "FAIL: $name: $(tail -1 "$tmp/$name.log")"; exit 1; }
}
for tier in $(choices sim.tier); do run "tier_$tier" --set sim.tier="$tier"; done
for kind in $(choices layout.kind); do
  run "layout_$kind" --set layout.kind="$kind"
  run "layout_cycle_$kind" --set layout.kind="$kind" --set sim.tier=cycle
done
for policy in $(choices l1.policy); do
  run "policy_$policy" --set l1.policy="$policy" --set dcache.enable=true --set dcache.policy="$policy"
  run "policy_cycle_$policy" --set l1.policy="$policy" --set sim.tier=cycle
done
for backend in $(choices dram.backend); do run "dram_$backend" --set sim.tier=cycle --set dram.backend="$backend"; done

python3 - "$tmp" "$(choices sim.tier)" "$(choices layout.kind)" "$(choices l1.policy)" "$(choices dram.backend)" <<'PY'
import json, sys
tmp, tiers, kinds, policies, backends = sys.argv[1], *[a.split() for a in sys.argv[2:]]
def stats(name): return json.load(open(f"{tmp}/{name}/stats.json"))
assert len(tiers) >= 3 and len(kinds) >= 3 and len(policies) >= 4 and len(backends) >= 2
runs = {f"tier_{t}": stats(f"tier_{t}") for t in tiers}
for group in [[f"layout_{k}" for k in kinds], [f"layout_cycle_{k}" for k in kinds],
              [f"policy_{p}" for p in policies], [f"policy_cycle_{p}" for p in policies],
              [f"dram_{b}" for b in backends], list(runs)]:
    s = [stats(n) for n in group]
    for n, x in zip(group, s):
        assert x["rays.total"] == s[0]["rays.total"], (n, "rays differ")
        assert x["traversal.node_fetches"] > 0 and x["dram.bytes.total"] > 0, n
for k in kinds:
    assert stats(f"layout_{k}")["layout.kind"] == k
for t in tiers:
    assert runs[f"tier_{t}"]["sim.tier"] == t
    assert ("sim.cycles" in runs[f"tier_{t}"]) == (t != "functional"), t
cycles = {b: stats(f"dram_{b}")["sim.cycles"] for b in backends}
assert len(set(cycles.values())) == len(backends), f"DRAM backends give the same cycles: {cycles}"
print("registries:", {"tiers": tiers, "layouts": kinds, "policies": policies, "dram": cycles})
PY
echo "PASS registries"
