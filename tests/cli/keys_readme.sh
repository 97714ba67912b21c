#!/usr/bin/env bash
# `rtusim keys`: the README's key table is its markdown output, and docs/stats.md's table that
# of `keys --stats` (no drift); json and text list the same keys.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

"$rtusim" keys --format markdown > "$tmp/keys.md"
sed -n '/<!-- rtusim keys: begin -->/,/<!-- rtusim keys: end -->/p' "$src/README.md" \
  | sed '1d;$d' > "$tmp/readme.md"
if ! diff -u "$tmp/readme.md" "$tmp/keys.md"; then
  echo "FAIL: README key table differs from 'rtusim keys --format markdown' (regenerate it)"
  exit 1
fi

# The stats keys' table in docs/stats.md is `keys --stats --format markdown`, likewise.
"$rtusim" keys --stats --format markdown > "$tmp/stats.md"
sed -n '/<!-- rtusim stats: begin -->/,/<!-- rtusim stats: end -->/p' "$src/docs/stats.md" \
  | sed '1d;$d' > "$tmp/docs_stats.md"
if ! diff -u "$tmp/docs_stats.md" "$tmp/stats.md"; then
  echo "FAIL: docs/stats.md differs from 'rtusim keys --stats --format markdown' (regenerate it)"
  exit 1
fi

"$rtusim" keys --format json > "$tmp/keys.json"
"$rtusim" keys > "$tmp/keys.txt"
python3 - "$tmp/keys.json" "$tmp/keys.txt" <<'PY'
import json, sys
keys = json.load(open(sys.argv[1]))
names = [k["key"] for k in keys]
assert len(names) == len(set(names)), "a key declared twice"
for k in keys:
    for field in ["type", "default", "range", "unit", "description"]:
        assert field in k, (k["key"], field)
    assert k["description"], f"{k['key']}: no description"
# The contract's keys are all declared.
for need in ["scene.path", "scene.camera", "camera.eye", "camera.target", "camera.up", "camera.vfov",
             "image.width", "image.height", "tracer.max_depth", "tracer.ray_order", "layout.kind",
             "l1.size", "l1.assoc", "l1.line", "l1.policy", "l1.model", "sim.tier",
             "sim.rays_in_flight", "dram.backend"]:
    assert need in names, f"missing key {need}"
# Defaults are JSON values of their type (not TOML text).
by = {k["key"]: k for k in keys}
assert by["l1.size"]["default"] == 8192 and by["scene.path"]["default"] == "builtin:cornell", \
    (by["l1.size"]["default"], by["scene.path"]["default"])
assert by["camera.up"]["default"] == [0.0, 1.0, 0.0] and by["camera.eye"]["default"] is None
text = open(sys.argv[2]).read().split()
for n in names:
    assert n in text, f"{n} not in the text listing"
PY
if "$rtusim" keys --format yaml > /dev/null 2>&1; then echo "FAIL: --format yaml accepted"; exit 1; fi
echo "PASS keys_readme"
