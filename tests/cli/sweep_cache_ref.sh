#!/usr/bin/env bash
# Every point of a cache sweep against the independent Python model (tests/cache_ref.py), not
# against the C++ caches that computed it: for each policy (lru, fifo, tree-plru, random) and
# geometry, the sweep's l1.misses equal cache_ref.py's misses over the node stream that
# `rtusim trace` exports for the same frame (dfl and odfl: 8-byte nodes never straddle a line,
# so one fetch is one line access).
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
py=${RTUSIM_PYTHON:-python3}
frame=(--set image.width=32 --set image.height=32 --set image.png=false --set image.heatmaps=false)
cat > "$tmp/spec.toml" <<'TOML'
[image]
width = 32
height = 32
png = false
heatmaps = false
[sweep]
layout.kind = ["dfl", "odfl"]
l1.policy = ["lru", "fifo", "tree-plru", "random"]
l1.line = [32, 64]
l1.assoc = [1, 4, "full"]
l1.size = [1024, 4096]
TOML
"$rtusim" sweep "$tmp/spec.toml" --out "$tmp/sweep" --no-plots > /dev/null
for layout in dfl odfl; do
  "$rtusim" trace "$src/configs/default.toml" "${frame[@]}" --set layout.kind=$layout \
    --out "$tmp/$layout.din" > /dev/null
done
"$py" - "$tmp" "$src/tests" <<'PY'
import csv, sys
sys.path.insert(0, sys.argv[2])
from cache_ref import misses
tmp = sys.argv[1]
traces = {k: [int(l.split()[1], 16) for l in open(f"{tmp}/{k}.din") if l.strip()]
          for k in ("dfl", "odfl")}
rows = list(csv.DictReader(open(f"{tmp}/sweep/results.csv", newline="")))
assert len(rows) == 2 * 4 * 2 * 3 * 2, len(rows)
bad, seen = 0, set()
for r in rows:
    size, line = int(r["l1.size"]), int(r["l1.line"])
    assoc = size // line if r["l1.assoc"] == "full" else int(r["l1.assoc"])
    want = misses(traces[r["layout.kind"]], size, assoc, line, r["l1.policy"])
    got = int(float(r["l1.misses"]))
    seen.add(r["l1.policy"])
    if got != want:
        bad += 1
        print(f"FAIL {r['layout.kind']} {r['l1.policy']} {size}/{r['l1.assoc']}/{line}: "
              f"sweep l1.misses {got}, cache_ref.py {want}")
assert seen == {"lru", "fifo", "tree-plru", "random"}, seen
print(f"sweep_cache_ref: {len(rows) - bad} passed, {bad} failed")
sys.exit(1 if bad else 0)
PY
