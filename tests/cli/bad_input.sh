#!/usr/bin/env bash
# Bad input: exit status 2, one line on stderr naming the file/key/line, no output left behind.
set -uo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
pass=0; fail=0

# expect_bad NAME PATTERN ARGS...: exit 2, exactly one stderr line matching PATTERN, no $tmp/out.
expect_bad() {
  local name=$1 pattern=$2; shift 2
  rm -rf "$tmp/out"
  "$@" > "$tmp/stdout" 2> "$tmp/stderr"
  local rc=$? lines
  lines=$(wc -l < "$tmp/stderr")
  if [ $rc -ne 2 ]; then echo "FAIL $name: exit $rc, want 2"; cat "$tmp/stderr"; fail=$((fail+1)); return; fi
  if [ "$lines" -ne 1 ]; then echo "FAIL $name: $lines stderr lines"; cat "$tmp/stderr"; fail=$((fail+1)); return; fi
  if ! grep -qE -- "$pattern" "$tmp/stderr"; then echo "FAIL $name: stderr lacks /$pattern/"; cat "$tmp/stderr"; fail=$((fail+1)); return; fi
  if [ -e "$tmp/out" ] && [ -n "$(ls -A "$tmp/out")" ]; then echo "FAIL $name: output left in $tmp/out"; fail=$((fail+1)); return; fi
  pass=$((pass+1))
}

printf '[image]\nwidth = 64\n[tracer]\nmax_dept = 3\n' > "$tmp/unknown.toml"
expect_bad unknown_key 'unknown.toml:4: tracer.max_dept: unknown key' "$rtusim" run "$tmp/unknown.toml" --out "$tmp/out"
printf '[image]\nwidth = "big"\n' > "$tmp/type.toml"
expect_bad wrong_type 'type.toml:2: image.width: expected an integer' "$rtusim" run "$tmp/type.toml" --out "$tmp/out"
printf '[image]\nheight = 0\n' > "$tmp/range.toml"
expect_bad out_of_range 'range.toml:2: image.height: must be between' "$rtusim" run "$tmp/range.toml" --out "$tmp/out"
printf '[image\n' > "$tmp/syntax.toml"
expect_bad toml_syntax 'syntax.toml:1' "$rtusim" run "$tmp/syntax.toml" --out "$tmp/out"
expect_bad missing_config 'nope.toml: config file not found' "$rtusim" run "$tmp/nope.toml" --out "$tmp/out"
expect_bad bad_set '--set tracer.max_depth=x' "$rtusim" run "$src/configs/default.toml" --set tracer.max_depth=x --out "$tmp/out"
expect_bad bad_layout "layout.kind: unknown value 'zfl'" "$rtusim" run "$src/configs/default.toml" --set layout.kind=zfl --out "$tmp/out"
printf '[scene]\npath = "missing/scene.gltf"\n' > "$tmp/noscene.toml"
expect_bad missing_scene 'scene.path: .*missing/scene.gltf' "$rtusim" run "$tmp/noscene.toml" --out "$tmp/out"
printf '{ "asset": {"version": "2.0"}, "meshes": [ ' > "$tmp/broken.gltf"
printf '[scene]\npath = "broken.gltf"\n' > "$tmp/broken.toml"
expect_bad bad_gltf 'broken.gltf' "$rtusim" run "$tmp/broken.toml" --out "$tmp/out"
expect_bad unknown_camera "scene.camera: no camera node 'nowhere'" "$rtusim" run "$src/configs/default.toml" --set scene.camera=nowhere --out "$tmp/out"
expect_bad unknown_option 'unknown-flag|extras|not expected' "$rtusim" run "$src/configs/default.toml" --unknown-flag
expect_bad hits_no_dir 'does not exist' "$rtusim" hits "$src/configs/default.toml" --out "$tmp/no/such/dir/h.bin"
expect_bad no_subcommand 'subcommand' "$rtusim"
expect_bad bad_tier "sim.tier: unknown value 'gpu'" "$rtusim" run "$src/configs/default.toml" --set sim.tier=gpu --out "$tmp/out"
expect_bad rtl_l1_functional 'l1.model: "rtl" needs sim.tier' "$rtusim" run "$src/configs/default.toml" --set l1.model=rtl --out "$tmp/out"
expect_bad bad_dram 'dram.channels: must be between' "$rtusim" run "$src/configs/default.toml" --set sim.tier=cycle --set dram.channels=0 --out "$tmp/out"
expect_bad bad_l1_geometry 'l1.size' "$rtusim" run "$src/configs/default.toml" --set l1.size=8000 --out "$tmp/out"

# An existing output directory keeps its files when a run fails.
mkdir -p "$tmp/keep" && echo precious > "$tmp/keep/stats.json"
"$rtusim" run "$tmp/unknown.toml" --out "$tmp/keep" 2>/dev/null
if [ "$(cat "$tmp/keep/stats.json")" = precious ] && [ "$(ls -A "$tmp/keep")" = stats.json ]; then pass=$((pass+1)); else echo "FAIL keep: existing output changed"; fail=$((fail+1)); fi

echo "bad_input: $pass passed, $fail failed"
[ $fail -eq 0 ]
