#!/usr/bin/env bash
# scripts/study_experiment.py on a small frame of one shared scene: study.csv holds the three
# layouts (and subtree-bfs) with the run's own stats, and study.md's percentages and ratios follow from the csv.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
scene=cornell_whitted
py=python3
[ -x "$src/.venv/bin/python" ] && py="$src/.venv/bin/python"
"$py" "$src/scripts/study_experiment.py" --scenes "$scene" --size 24 --out "$tmp/study" --rtusim "$rtusim" > /dev/null
python3 - "$tmp/study" "$scene" <<'PY'
import csv, json, re, sys
out, scene = sys.argv[1], sys.argv[2]
rows = list(csv.DictReader(open(f"{out}/study.csv")))
assert [r["layout"] for r in rows] == ["dfl", "odfl", "subtree", "subtree-bfs"], rows
stats = json.load(open(f"{out}/{scene}/stats.json"))
for r in rows:
    p = f"layout.{r['layout']}."
    assert int(r["node_dram_bytes"]) == stats[p + "dram.bytes.nodes"], r
    assert int(r["node_memory_bytes"]) == stats[p + "tree.bytes"], r
    assert int(r["rays"]) == stats["rays.total"] and int(r["rays"]) >= 24 * 24
d, o, t, b = (int(r["node_dram_bytes"]) for r in rows)
md = open(f"{out}/study.md").read()
row = next(l for l in md.splitlines() if l.startswith(f"| {scene} |"))
cells = [c.strip() for c in row.strip("|").split("|")]
assert cells[7] == f"{-100 * (1 - o / d):+.1f}%", (cells[7], d, o)
assert cells[8] == f"{-100 * (1 - o / t):+.1f}%", (cells[8], t, o)
mem = [int(r["node_memory_bytes"]) for r in rows]
assert cells[12] == f"{mem[2] / mem[0]:.2f}x", cells[12]
assert cells[13] == f"{mem[3] / mem[0]:.2f}x", cells[13]
assert mem[1] == mem[0] and mem[3] >= mem[2] > mem[0], mem
PY
echo "study_experiment: 1 passed, 0 failed"
