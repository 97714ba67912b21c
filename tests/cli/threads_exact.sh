#!/usr/bin/env bash
# --threads N never changes a result: run (stats.json but its timing keys, image.png, every
# heatmap and diff image), hits and trace (din and bin) are byte-identical for 1, 2 and 7
# threads, on every layout, in both ray orders, with and without the data cache, and for every
# node-L1 replacement policy.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# Every registered layout (the range of layout.kind: "[one of: a, b, ...]").
layouts=$("$rtusim" keys --format json | python3 -c '
import json, re, sys
key = next(k for k in json.load(sys.stdin) if k["key"] == "layout.kind")
print(" ".join(re.findall(r"[\w-]+", key["range"].split(":", 1)[1])))')
test -n "$layouts"
list=$(python3 -c 'import sys; print("[" + ",".join(f"\"{k}\"" for k in sys.argv[1:]) + "]")' $layouts)
common=(--set image.width=40 --set image.height=32 --set l1.size=1024)

# Stats without the keys that time the run.
strip() {
  python3 - "$1" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(json.dumps({k: v for k, v in s.items() if "seconds" not in k and "per_second" not in k or k.startswith("report.")}, sort_keys=True, indent=1))
PY
}

for order in recursive wavefront; do
  for dcache in false true; do
    for t in 1 2 7; do
      d="$tmp/$order-$dcache-$t"
      "$rtusim" run "$src/configs/default.toml" "${common[@]}" --set tracer.ray_order=$order \
        --set dcache.enable=$dcache --set "layout.kind=$list" --threads $t --out "$d" > /dev/null
      strip "$d/stats.json" > "$d/stats.stripped"
      rm "$d/stats.json"
      if [ $t -gt 1 ]; then
        base="$tmp/$order-$dcache-1"
        diff -r "$base" "$d" || { echo "run differs: $order dcache=$dcache threads=$t" >&2; exit 1; }
      fi
    done
  done
  for layout in $layouts; do
    for format in din bin; do
      for t in 1 2 7; do
        "$rtusim" trace "$src/configs/default.toml" "${common[@]}" --set tracer.ray_order=$order \
          --set layout.kind=$layout --format $format --threads $t --out "$tmp/t$t.$format" > /dev/null
      done
      cmp "$tmp/t1.$format" "$tmp/t2.$format"
      cmp "$tmp/t1.$format" "$tmp/t7.$format"
    done
  done
done
# The recording threads count repeated node-L1 hits and straight-to-DRAM fetches instead of
# logging them (tracer/fetch_log.h): the same answer for every replacement policy, and with
# lines smaller than a node (a node fetch touches two lines) or holding many nodes.
for policy in lru tree-plru fifo random; do
  for line in 4 64 256; do
    for t in 1 2; do
      d="$tmp/policy-$policy-$line-$t"
      "$rtusim" run "$src/configs/default.toml" "${common[@]}" --set tracer.ray_order=wavefront \
        --set l1.policy=$policy --set l1.line=$line --set l1.assoc=2 --threads $t --out "$d" > /dev/null
      strip "$d/stats.json" > "$d/stats.stripped"
      rm "$d/stats.json"
    done
    diff -r "$tmp/policy-$policy-$line-1" "$tmp/policy-$policy-$line-2" ||
      { echo "run differs: l1.policy=$policy l1.line=$line" >&2; exit 1; }
  done
done

# The run really recorded something: misses and pixel heatmaps for every layout.
python3 - "$tmp/recursive-false-7/stats.stripped" $layouts <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
for kind in sys.argv[2:]:
    assert s[f"layout.{kind}.l1.misses"] > 0 and s[f"layout.{kind}.l1.hits"] > 0, kind
PY
for layout in $layouts; do test -s "$tmp/recursive-false-7/heatmap_$layout.png"; done

for t in 1 2 7; do
  "$rtusim" hits "$src/configs/default.toml" "${common[@]}" --threads $t --out "$tmp/h$t.rth" > /dev/null
done
cmp "$tmp/h1.rth" "$tmp/h2.rth"
cmp "$tmp/h1.rth" "$tmp/h7.rth"
echo "threads_exact: ok ($layouts)"
