#!/usr/bin/env bash
# Every stats.json key is declared (util/stat_decl.h) with a kind, unit and description, as
# `rtusim keys --stats` lists them: runs of every tier and mode (functional, interleaved, timed
# in runs, cycle with a data cache and both DRAM backends, rtl, sampled with two layouts, a chip
# with an L2) are checked key by key against the declarations and their documented forms.
set -uo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
py=${RTUSIM_PYTHON:-python3}
cfg=$src/configs/default.toml
small=(--set image.width=24 --set image.height=24 --set image.png=false)
two='layout.kind=["dfl","odfl"]'
fail=0
i=0
while read -r args; do
  i=$((i+1))
  # shellcheck disable=SC2086
  if ! eval "\"$rtusim\" run \"$cfg\" \"\${small[@]}\" $args --out \"$tmp/run$i\"" \
      > /dev/null 2> "$tmp/err"; then
    # A build without the RTL L1 (the sanitizer job's) cannot run the rtl tier.
    if grep -qE "built without the RTL|built: none" "$tmp/err"; then echo "note: no rtl tier in this build"
    else echo "FAIL run $args: $(cat "$tmp/err")"; fail=1; fi
  fi
done <<'RUNS'
--set "layout.kind=[\"dfl\",\"odfl\"]"
--set functional.rays_in_flight=8
--set functional.timed=true --set functional.rays_in_flight=8 --set functional.timed_segments=4
--set sim.tier=cycle --set dcache.enable=true --set "layout.kind=[\"dfl\",\"odfl\"]"
--set sim.tier=cycle --set dram.backend=fixed
--set sim.tier=rtl
--set sim.tier=cycle --set sample.rate=0.5 --set "layout.kind=[\"dfl\",\"odfl\"]"
--set sample.rate=0.5 --set sample.target_ci=0.5 --set tracer.ray_order=wavefront
--set chip.units=3 --set l2.enable=true --set dcache.enable=true --set "layout.kind=[\"dfl\",\"odfl\"]"
--set chip.units=2
RUNS
"$rtusim" keys --stats --format json > "$tmp/keys.json" || { echo "FAIL keys --stats"; exit 1; }
"$py" - "$tmp" <<'PY' || fail=1
import glob, json, re, sys
d = sys.argv[1]
decls = json.load(open(f"{d}/keys.json"))
names = [k["key"] for k in decls]
assert len(names) == len(set(names)), "a stats key declared twice"
for k in decls:
    assert k["kind"] in ("counter", "ratio", "timing", "property"), k
    assert k["description"], k
def regex(key):
    r = re.escape(key).replace(re.escape("<stream>"), "(nodes|lists|triangles)")
    return re.compile(r.replace(re.escape("<level>"), "(l1|dcache|l2)") + "$")
pats = [(regex(k["key"]), k) for k in decls]
def declared(key):
    return next((k for p, k in pats if p.match(key)), None)
def find(key):
    key = re.sub(r"^(layout\.[a-z0-9_-]+\.)?(units\.[0-9]+\.)?", "", key)
    if declared(key): return declared(key)
    m = re.match(r"^(sample\.diff\.[a-z0-9_-]+-[a-z0-9_-]+\.)?(.*?)(\.ci95_(low|high))?$", key)
    if m.group(1) or m.group(3):
        k = declared(m.group(2))
        if k and k["kind"] == "counter": return k
    return None
runs = sorted(glob.glob(f"{d}/run*/stats.json"))
assert len(runs) >= 9, runs
missing = set()
seen = set()
for f in runs:
    for key in json.load(open(f)):
        k = find(key)
        if k is None: missing.add(key)
        else: seen.add(k["key"])
assert not missing, f"undeclared stats keys: {sorted(missing)}"
# Each declaration is written by some run (no stale declaration); these need another setting.
unwritten = set(names) - seen - {"sample.target_met", "sample.rays_warmed"}
assert not unwritten, f"declared but written by no run: {sorted(unwritten)}"
# Kinds the rest of the program relies on.
kind = {k["key"]: k["kind"] for k in decls}
for key, want in [("l1.misses", "counter"), ("l2.misses", "counter"), ("dram.bytes.total", "counter"),
                  ("sim.cycles", "counter"), ("trace.seconds", "timing"), ("run.seconds", "timing"),
                  ("l1.miss_rate", "ratio"), ("tree.nodes", "property")]:
    assert kind[declared(key)["key"]] == want, key
print(f"{len(runs)} runs, {len(names)} declarations, every key declared")
PY
[ $fail -eq 0 ] && echo "PASS stats_declared" || { echo "FAIL stats_declared"; exit 1; }
