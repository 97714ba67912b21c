#!/usr/bin/env bash
# The shape of sim/: no include cycle between folders, and SystemC only where a SystemC module
# is (no *_params.h pulls it in, even indirectly; nothing under config/, cache/, tier/, app/ ...).
set -euo pipefail
src=$2
python3 - "$src/sim" <<'PY'
import os, re, sys
root = sys.argv[1]
edges, systemc = {}, []
for d, _, files in os.walk(root):
    for f in files:
        if not f.endswith((".h", ".cpp")): continue
        path = os.path.join(d, f)
        rel = os.path.relpath(path, root)
        folder = rel.split("/")[0]
        text = open(path).read()
        for m in re.finditer(r'#include "([a-z_0-9]+)/', text):
            if m.group(1) != folder: edges.setdefault(folder, set()).add(m.group(1))
        if re.search(r"#include <(systemc|tlm)", text): systemc.append(rel)
def reach(a):
    seen, todo = set(), [a]
    while todo:
        for y in edges.get(todo.pop(), ()):
            if y not in seen: seen.add(y); todo.append(y)
    return seen
cycles = sorted({tuple(sorted((a, b))) for a in edges for b in reach(a) if b != a and a in reach(b)})
assert not cycles, f"folder include cycles: {cycles}"
bad = [p for p in systemc if p.endswith("_params.h") or p.split("/")[0] in
       ("config", "cache", "layout", "tier", "app", "trace", "tracer", "traversal", "scene", "kdtree")]
assert not bad, f"SystemC included outside the SystemC modules: {bad}"
# No params header pulls SystemC in, directly or through what it includes.
def includes(rel):
    path = os.path.join(root, rel)
    return re.findall(r'#include "([^"]+)"', open(path).read()) if os.path.isfile(path) else []
for d, _, files in os.walk(root):
    for f in files:
        if not f.endswith("_params.h"): continue
        start = os.path.relpath(os.path.join(d, f), root)
        seen, todo = {start}, [start]
        while todo:
            for inc in includes(todo.pop()):
                if inc not in seen: seen.add(inc); todo.append(inc)
        assert not seen & set(systemc), f"{start} pulls in SystemC through {sorted(seen & set(systemc))}"
print(f"{len(edges)} folders, no cycles; SystemC in {len(systemc)} files: {', '.join(sorted(systemc))}")
PY
echo "PASS structure"
