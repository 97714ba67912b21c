#!/usr/bin/env bash
# rtusim sweep end to end: every point equals its own `rtusim run` (every policy, line size,
# "full", the data cache, subtree with 32-byte lines, a timed point); the product and a group
# expand as specified; kills at several moments then a rerun give results.csv byte for byte;
# a changed spec in an existing DIR and every bad spec exit 2 with one line, leaving nothing.
set -uo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
py=${RTUSIM_PYTHON:-python3}
pass=0; fail=0
ok() { pass=$((pass+1)); }
bad() { echo "FAIL $*"; fail=$((fail+1)); }

# 1. Exactness against `rtusim run`, point by point.
cat > "$tmp/exact.toml" <<'TOML'
[image]
width = 40
height = 40
png = false
[sweep]
layout.kind = ["dfl", "subtree"]
l1.policy = ["lru", "fifo", "tree-plru", "random"]
l1.line = [32, 64, 128]
l1.assoc = [1, 4, "full"]
l1.size = [1024, 8192]
TOML
"$rtusim" sweep "$tmp/exact.toml" --out "$tmp/exact" --no-plots > /dev/null || bad "exact sweep failed"
rows=$(($(wc -l < "$tmp/exact/results.csv") - 1))
[ "$rows" -eq 144 ] && ok || bad "product: $rows rows, want 2x4x3x3x2 = 144"
"$py" "$src/tests/cli/sweep_check.py" "$rtusim" "$tmp/exact" 5 \
  layout.kind,l1.policy,l1.line,l1.assoc,l1.size && ok || bad "exact: sweep differs from rtusim run"

# 2. The data cache, a group of keys that vary together, and a timed point.
cat > "$tmp/group.toml" <<'TOML'
[image]
width = 32
height = 32
png = false
[dcache]
enable = true
[sweep]
layout.kind = ["odfl", "subtree"]
l1.line = [32]
dcache.policy = ["lru", "fifo"]
dcache.line = [32, 128]
dcache.assoc = [2, "full"]
dcache.size = [2048, 16384]
[[sweep.group.g]]
tracer.max_depth = 2
[[sweep.group.g]]
tracer.max_depth = 1
sim.tier = "cycle"
TOML
"$rtusim" sweep "$tmp/group.toml" --out "$tmp/group" --no-plots > /dev/null || bad "group sweep failed"
rows=$(($(wc -l < "$tmp/group/results.csv") - 1))
[ "$rows" -eq 64 ] && ok || bad "group product: $rows rows, want 2 entries x 2x2x2x2x2 = 64"
head -1 "$tmp/group/results.csv" | grep -q '^sim.tier,tracer.max_depth,layout.kind,l1.line,dcache.policy,dcache.line,dcache.assoc,dcache.size,' \
  && ok || bad "group columns: $(head -1 "$tmp/group/results.csv" | cut -c1-120)"
[ "$(grep -c ',cycle\|^cycle,' "$tmp/group/results.csv")" -eq 32 ] && ok || bad "group: want 32 cycle rows"
"$py" "$src/tests/cli/sweep_check.py" "$rtusim" "$tmp/group" 3 \
  sim.tier,tracer.max_depth,layout.kind,l1.line,dcache.policy,dcache.line,dcache.assoc,dcache.size \
  && ok || bad "group: sweep differs from rtusim run"

# 2b. Points the one-pass evaluation cannot stand for (the functional tier's interleaved and
# timed modes, sampled runs) each run alone, as rtusim run runs them; several layouts in the base
# config and none swept: one point per layout.
cat > "$tmp/modes.toml" <<'TOML'
[image]
width = 16
height = 16
png = false
[tracer]
max_depth = 2
ray_order = "wavefront"
[layout]
kind = ["dfl", "odfl"]
[sweep]
functional.rays_in_flight = [1, 8]
functional.timed = [false, true]
sample.rate = [1.0, 0.5]
TOML
"$rtusim" sweep "$tmp/modes.toml" --out "$tmp/modes" --no-plots > /dev/null || bad "modes sweep failed"
rows=$(($(wc -l < "$tmp/modes/results.csv") - 1))
[ "$rows" -eq 16 ] && ok || bad "modes: $rows rows, want 2x2x2 x 2 layouts = 16"
head -1 "$tmp/modes/results.csv" | grep -q 'estimate.cycles' && ok || bad "modes: no estimate.cycles column"
head -1 "$tmp/modes/results.csv" | grep -q 'rays_simulated_per_second' && bad "modes: a wall-clock rate in results.csv" || ok
"$py" "$src/tests/cli/sweep_check.py" "$rtusim" "$tmp/modes" 1 \
  functional.rays_in_flight,functional.timed,sample.rate,layout.kind && ok || bad "modes: sweep differs from rtusim run"

# 2c. A relative scene.path in a group: read against the spec's directory; its results.csv cell
# is that path made absolute, so the point reruns from anywhere.
mkdir -p "$tmp/rel/sub" && python3 "$src/tests/cli/make_bad_inputs.py" "$tmp/rel/sub" > /dev/null
printf '[image]\nwidth = 16\nheight = 16\npng = false\n[camera]\neye = [0.2, 0.2, 2]\ntarget = [0.2, 0.2, 0]\n[sweep]\nl1.size = [4096, 8192]\n[[sweep.group.s]]\nscene.path = "sub/good.gltf"\n[[sweep.group.s]]\nscene.path = "builtin:cornell"\n' > "$tmp/rel/spec.toml"
(cd / && "$rtusim" sweep "$tmp/rel/spec.toml" --out "$tmp/relout" --no-plots > /dev/null) || bad "relative scene sweep failed"
grep -q "^$tmp/rel/sub/good.gltf," "$tmp/relout/results.csv" && ok || bad "relative scene: cell $(sed -n 2p "$tmp/relout/results.csv" | cut -d, -f1)"
(cd / && "$py" "$src/tests/cli/sweep_check.py" "$rtusim" "$tmp/relout" 1 scene.path,l1.size) \
  && ok || bad "relative scene: sweep differs from rtusim run"

# 3. Resume: killed (with its jobs) at several moments, then rerun: the same results.csv.
cat > "$tmp/resume.toml" <<'TOML'
[image]
width = 40
height = 40
png = false
[sweep]
tracer.max_depth = [0, 1, 2, 3, 4, 5]
layout.kind = ["dfl", "odfl"]
l1.assoc = [2, "full"]
l1.size = [2048, 4096]
TOML
"$rtusim" sweep "$tmp/resume.toml" --out "$tmp/whole" --no-plots > /dev/null || bad "resume reference failed"
for delay in 0.05 0.3 0.6 0.9 1.4; do
  rm -rf "$tmp/killed"
  setsid "$rtusim" sweep "$tmp/resume.toml" --out "$tmp/killed" --threads 2 --no-plots > /dev/null 2>&1 &
  pid=$!
  sleep "$delay"
  kill -KILL -- -"$pid" 2> /dev/null
  wait "$pid" 2> /dev/null
  for _ in 1 2; do  # a second kill mid-rerun, then a rerun to the end
    setsid "$rtusim" sweep "$tmp/resume.toml" --out "$tmp/killed" --threads 2 --no-plots > /dev/null 2>&1 &
    pid=$!; sleep 0.2; kill -KILL -- -"$pid" 2> /dev/null; wait "$pid" 2> /dev/null
  done
  "$rtusim" sweep "$tmp/resume.toml" --out "$tmp/killed" --no-plots > /dev/null || bad "resume after $delay s failed"
  cmp -s "$tmp/whole/results.csv" "$tmp/killed/results.csv" && ok || bad "resume after $delay s: results.csv differs"
done
# Damaged job files (cut short, a row removed, empty JSON) are run again, not an internal error.
cp -r "$tmp/whole" "$tmp/damaged" && rm "$tmp/damaged/results.csv"
head -c 40 "$tmp/whole/jobs/0.json" > "$tmp/damaged/jobs/0.json"
echo '{}' > "$tmp/damaged/jobs/1.json"
python3 - "$tmp/damaged/jobs/2.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
j["rows"].pop(next(iter(j["rows"])))
json.dump(j, open(sys.argv[1], "w"))
j = json.load(open(sys.argv[1].replace("2.json", "3.json")))
j["rows"][next(iter(j["rows"]))] = {}
json.dump(j, open(sys.argv[1].replace("2.json", "3.json"), "w"))
PY
"$rtusim" sweep "$tmp/resume.toml" --out "$tmp/damaged" --no-plots > /dev/null 2> "$tmp/stderr" \
  && cmp -s "$tmp/whole/results.csv" "$tmp/damaged/results.csv" && ok || bad "damaged job files: $(cat "$tmp/stderr")"

# 4. A changed spec in a directory holding a sweep; bad specs. Exit 2, one line, no output.
expect_bad() {
  local name=$1 pattern=$2 spec=$3 out=$4
  "$rtusim" sweep "$spec" --out "$out" --no-plots > /dev/null 2> "$tmp/stderr"
  local rc=$?
  if [ $rc -ne 2 ]; then bad "$name: exit $rc, want 2"; cat "$tmp/stderr"; return; fi
  if [ "$(wc -l < "$tmp/stderr")" -ne 1 ]; then bad "$name: not one stderr line"; cat "$tmp/stderr"; return; fi
  if ! grep -qE -- "$pattern" "$tmp/stderr"; then bad "$name: stderr lacks /$pattern/"; cat "$tmp/stderr"; return; fi
  ok
}
sed 's/l1.size = \[2048, 4096\]/l1.size = [2048, 8192]/' "$tmp/resume.toml" > "$tmp/changed.toml"
expect_bad changed_spec 'holds a different sweep' "$tmp/changed.toml" "$tmp/whole"
spec_with() { printf '[image]\nwidth = 16\nheight = 16\n[sweep]\n%s\n' "$2" > "$tmp/$1.toml"; }
spec_with unknown 'l1.sise = [1024]'
expect_bad unknown_key 'unknown.toml:5: \[sweep\] l1.sise = 1024: l1.sise: unknown key' "$tmp/unknown.toml" "$tmp/none"
spec_with empty 'l1.size = []'
expect_bad empty_list 'empty.toml:5: \[sweep\] l1.size: empty list' "$tmp/empty.toml" "$tmp/none"
spec_with value 'l1.policy = ["lru", "mru"]'
expect_bad invalid_value "value.toml:5: \[sweep\] l1.policy = mru: l1.policy: unknown value 'mru'" "$tmp/value.toml" "$tmp/none"
spec_with notlist 'l1.size = 1024'
expect_bad not_a_list 'notlist.toml:5: \[sweep\] l1.size = 1024: expected a list' "$tmp/notlist.toml" "$tmp/none"
spec_with point $'l1.size = [1024]\nl1.line = [128]\nl1.assoc = [16]'
expect_bad invalid_point 'point.toml: \[sweep\] point 0 \(l1.line = 128, l1.assoc = 16, l1.size = 1024\): l1.size: 1024 is smaller than l1.line x l1.assoc' "$tmp/point.toml" "$tmp/none"
# A value that fails alone on the base config but holds with the other swept values: valid.
spec_with together $'l1.assoc = [3, "full"]\nl1.size = [3072, 6144]'
"$rtusim" sweep "$tmp/together.toml" --out "$tmp/together" --no-plots > /dev/null 2> "$tmp/stderr" \
  && [ "$(($(wc -l < "$tmp/together/results.csv") - 1))" -eq 4 ] && ok || bad "together: $(cat "$tmp/stderr")"
spec_with apart $'l1.assoc = [3, "full"]\nl1.size = [3072, 8192]'
expect_bad value_with_another 'apart.toml:5: \[sweep\] l1.assoc = 3: l1.size: 8192 is not a multiple of l1.line x l1.assoc' "$tmp/apart.toml" "$tmp/none"
spec_with scene $'[[sweep.group.s]]\nscene.path = "nowhere.gltf"'
expect_bad missing_scene 'scene.toml:5: \[sweep.group.s\] scene.path = nowhere.gltf: scene.path: .*nowhere.gltf not found' "$tmp/scene.toml" "$tmp/none"
spec_with layouts $'l1.size = [1024]\n[[sweep.group.g]]\nlayout.kind = ["dfl", "odfl"]'
expect_bad point_with_layouts 'layouts.toml:6: \[sweep.group.g\] layout.kind = .*: layout.kind: a point has one layout' "$tmp/layouts.toml" "$tmp/none"
spec_with notgroup $'l1.size = [1024]\n[sweep.group]\ng = 3'
expect_bad group_not_entries 'notgroup.toml:7: \[sweep.group.g\]: expected \[\[sweep.group.g\]\] entries' "$tmp/notgroup.toml" "$tmp/none"
printf '[image]\nwidth = 16\n' > "$tmp/nosweep.toml"
expect_bad no_sweep_table 'nosweep.toml: \[sweep\]: missing' "$tmp/nosweep.toml" "$tmp/none"
spec_with twice $'l1.size = [1024]\n[[sweep.group.a]]\nl1.size = 2048'
expect_bad key_twice 'twice.toml:5: \[sweep\] l1.size: also swept by \[sweep.group.a\]' "$tmp/twice.toml" "$tmp/none"
spec_with dupvalue 'l1.size = [1024, 1024]'
expect_bad value_twice 'dupvalue.toml:5: \[sweep\] l1.size: value 1024 is listed twice' "$tmp/dupvalue.toml" "$tmp/none"
spec_with setswept 'l1.size = [1024, 2048]'
"$rtusim" sweep "$tmp/setswept.toml" --set l1.size=4096 --out "$tmp/none" --no-plots > /dev/null 2> "$tmp/stderr"
[ $? -eq 2 ] && [ "$(wc -l < "$tmp/stderr")" -eq 1 ] && grep -q -- '--set l1.size=4096: l1.size is swept by' "$tmp/stderr" \
  && ok || { bad "set_swept_key: $(cat "$tmp/stderr")"; }
expect_bad out_is_file 'results.csv: exists and is not a directory' "$tmp/setswept.toml" "$tmp/exact/results.csv"
"$rtusim" sweep "$tmp/setswept.toml" --scheduler notanaddress --out "$tmp/none" --no-plots > /dev/null 2> "$tmp/stderr"
[ $? -eq 2 ] && grep -q -- '--scheduler notanaddress: expected tcp://HOST:PORT' "$tmp/stderr" && ok || bad "bad_scheduler: $(cat "$tmp/stderr")"
# A scene that does not parse, or a camera it lacks: found before anything runs (each distinct
# scene and camera loaded once), named by its entry's line, no directory left; the other entry
# valid, so its job would have finished first.
printf '{ "asset": {"version": "2.0"}, "meshes": [ ' > "$tmp/broken.gltf"
spec_with broken $'[[sweep.group.s]]\nscene.path = "broken.gltf"'
expect_bad bad_scene_before_running 'broken.toml:5: \[sweep.group.s\] scene.path = broken.gltf: scene.path: .*broken.gltf: cannot parse glTF' "$tmp/broken.toml" "$tmp/none"
[ -e "$tmp/none" ] && bad "a bad spec left $tmp/none" || ok
# ... nor the parent directories it made for --out.
expect_bad bad_scene_parents 'broken.toml:5: ' "$tmp/broken.toml" "$tmp/made/for/it"
# The value that sets the scene is named, not another scene or camera key swept beside it.
spec_with vfovscene $'camera.vfov = [30, 60]\nscene.path = ["builtin:cornell", "broken.gltf"]'
expect_bad bad_scene_beside_vfov 'vfovscene.toml:6: \[sweep\] scene.path = broken.gltf: scene.path: ' "$tmp/vfovscene.toml" "$tmp/none"
spec_with nocam $'[[sweep.group.s]]\nscene.path = "builtin:cornell"\n[[sweep.group.s]]\nscene.path = "builtin:cornell"\nscene.camera = "nowhere"'
expect_bad bad_camera_before_running "nocam.toml:7: \\[sweep.group.s\\] scene.camera = nowhere, scene.path = builtin:cornell: scene.camera: no camera node 'nowhere'" "$tmp/nocam.toml" "$tmp/none"
[ -e "$tmp/made" ] && bad "a bad spec left $tmp/made" || ok
# The user's own --set is named as such; a table --set around a swept key counts as setting it;
# integers are one value however written.
expect_set() {
  local name=$1 pattern=$2; shift 2
  "$rtusim" sweep "$@" --out "$tmp/none" --no-plots > /dev/null 2> "$tmp/stderr"
  [ $? -eq 2 ] && [ "$(wc -l < "$tmp/stderr")" -eq 1 ] && grep -qE -- "$pattern" "$tmp/stderr" && [ ! -e "$tmp/none" ] \
    && ok || bad "$name: $(cat "$tmp/stderr")"
}
expect_set user_set 'base config: --set l1.assoc=3: ' "$tmp/setswept.toml" --set l1.assoc=3
expect_set table_set '--set l1=\{size=2048\}: l1.size is swept by' "$tmp/setswept.toml" --set 'l1={size=2048}'
spec_with hexdup 'l1.size = [8192, 0x2000]'
expect_bad hex_value_twice 'hexdup.toml:5: \[sweep\] l1.size: value .* is listed twice' "$tmp/hexdup.toml" "$tmp/none"
# A relative --set scene.path is read against the spec's directory, as `rtusim run SPEC` reads it.
mkdir -p "$tmp/rs/scenes" && python3 "$src/tests/cli/make_bad_inputs.py" "$tmp/rs/scenes" > /dev/null
printf '[image]\nwidth = 8\nheight = 8\n[camera]\neye = [0.2, 0.2, 2]\ntarget = [0.2, 0.2, 0]\n[sweep]\nl1.size = [1024]\n' > "$tmp/rs/spec.toml"
(cd "$tmp" && "$rtusim" sweep rs/spec.toml --set scene.path=scenes/good.glb --out rs/out --no-plots > /dev/null) && ok || bad "relative --set scene.path"
# DIR/base.toml carries the sweep's --set: a point is `rtusim run DIR/base.toml --set KEY=VALUE`.
"$rtusim" sweep "$tmp/setswept.toml" --set image.width=24 --out "$tmp/withset" --no-plots > /dev/null || bad "sweep with --set failed"
"$rtusim" run "$tmp/withset/base.toml" --set l1.size=2048 --out "$tmp/withset_run" > /dev/null || bad "base.toml run failed"
"$py" - "$tmp/withset" "$tmp/withset_run" <<'PY' && ok || bad "base.toml lacks the --set"
import csv, json, sys
row = [r for r in csv.DictReader(open(sys.argv[1] + "/results.csv")) if r["l1.size"] == "2048"][0]
run = json.load(open(sys.argv[2] + "/stats.json"))
assert int(row["dram.bytes.nodes"]) == run["dram.bytes.nodes"] and int(row["rays.primary"]) == 24 * 16, (row["dram.bytes.nodes"], run["dram.bytes.nodes"])
PY

echo "sweep: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
