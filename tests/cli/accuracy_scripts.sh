#!/usr/bin/env bash
# scripts/interleave_bias.py on a small frame of the built-in room under two names: one CSV per
# name, its rows the runs' own stats; with one ray in flight every mode is the functional tier
# and equals the cycle tier's node bytes. Bad --names: exit 2 naming the problem, nothing written.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
py=python3
[ -x "$src/.venv/bin/python" ] && py="$src/.venv/bin/python"
cfg="$src/configs/default.toml"
cp "$cfg" "$tmp/room.toml"
"$py" "$src/scripts/interleave_bias.py" "$cfg" "$tmp/room.toml" --names a b --size 20 \
  --in-flight 1 4 --out "$tmp/ib" --rtusim "$rtusim" > "$tmp/log"
[ "$(ls "$tmp/ib")" = "$(printf 'interleave_bias_a.csv\ninterleave_bias_b.csv')" ] || {
  ls "$tmp/ib"; exit 1; }
"$rtusim" run "$cfg" --set image.width=20 --set image.height=20 --set tracer.ray_order=wavefront \
  --set sim.tier=cycle --set sim.rays_in_flight=4 --set image.png=false --set image.heatmaps=false \
  --out "$tmp/c4" > /dev/null
python3 - "$tmp/ib" "$tmp/c4/stats.json" <<'PY'
import csv, json, sys
d, c4 = sys.argv[1], json.load(open(sys.argv[2]))
for name in "ab":
    rows = list(csv.DictReader(open(f"{d}/interleave_bias_{name}.csv")))
    assert [(r["scene"], r["rays_in_flight"]) for r in rows] == [(name, "1"), (name, "4")], rows
    one, four = rows
    for k in ("functional_node_bytes", "interleaved_node_bytes", "timed_node_bytes"):
        assert one[k] == one["cycle_node_bytes"], (k, one)
    assert int(four["cycle_node_bytes"]) == c4["dram.bytes.nodes"], four
    assert int(four["cycle_cycles"]) == c4["sim.cycles"], four
    err = int(four["interleaved_node_bytes"]) / int(four["cycle_node_bytes"]) - 1
    assert abs(float(four["interleaved_error"]) - err) < 1e-12, four
PY
# Bad arguments: one line, exit 2, no output directory.
set +e
"$py" "$src/scripts/interleave_bias.py" "$cfg" --names a b --out "$tmp/bad" --rtusim "$rtusim" \
  > /dev/null 2> "$tmp/err"; rc=$?
set -e
[ $rc -eq 2 ] && grep -q "2 names for 1 configs" "$tmp/err" && [ ! -e "$tmp/bad" ] || {
  echo "rc=$rc"; cat "$tmp/err"; exit 1; }
echo "accuracy_scripts: ok"
