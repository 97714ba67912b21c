#!/usr/bin/env bash
# The C++ cache model against an independent one: a din trace exported by `rtusim trace`, replayed
# through tests/cache_ref.py (plain Python), gives exactly the l1.misses of `rtusim run` and the
# misses of `rtusim replay` of that trace, for lru, fifo, tree-plru and random, two geometries
# (8K/4-way/64B and 4K/2-way/32B), dfl and odfl (8-byte nodes never straddle a line, so one
# fetch is one line access).
set -uo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
pass=0; fail=0
cfg=$src/configs/default.toml
small=(--set image.width=40 --set image.height=40 --set image.png=false --set image.heatmaps=false)

for layout in dfl odfl; do
  "$rtusim" trace "$cfg" "${small[@]}" --set layout.kind=$layout --out "$tmp/$layout.din" > /dev/null ||
    { echo "FAIL trace $layout"; fail=$((fail+1)); continue; }
  for geom in "8192 4 64" "4096 2 32"; do
    read -r size assoc line <<< "$geom"
    python3 "$src/tests/cache_ref.py" "$tmp/$layout.din" $size $assoc $line lru,fifo,tree-plru,random > "$tmp/ref.txt" ||
      { echo "FAIL cache_ref.py $layout $geom"; fail=$((fail+1)); continue; }
    for policy in lru fifo tree-plru random; do
      "$rtusim" run "$cfg" "${small[@]}" --set layout.kind=$layout --set l1.size=$size \
        --set l1.assoc=$assoc --set l1.line=$line --set l1.policy=$policy --out "$tmp/run" > /dev/null
      got=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['l1.misses'])" "$tmp/run/stats.json")
      want=$(awk -v p=$policy '$1 == p {print $2}' "$tmp/ref.txt")
      if [ -n "$want" ] && [ "$got" = "$want" ]; then
        pass=$((pass+1))
      else
        echo "FAIL $layout $size/$assoc/$line $policy: run l1.misses $got, cache_ref.py $want"; fail=$((fail+1))
      fi
      # `rtusim replay` of the same trace (its own cache forms: 4-way LRU is Lru4Cache).
      replayed=$("$rtusim" replay "$tmp/$layout.din" --set l1.size=$size --set l1.assoc=$assoc \
        --set l1.line=$line --set l1.policy=$policy | awk '$1 == "misses" {print $2}')
      if [ -n "$want" ] && [ "$replayed" = "$want" ]; then
        pass=$((pass+1))
      else
        echo "FAIL $layout $size/$assoc/$line $policy: replay misses $replayed, cache_ref.py $want"; fail=$((fail+1))
      fi
    done
  done
done
echo "trace_cache_ref: $pass passed, $fail failed"
[ $fail -eq 0 ]
