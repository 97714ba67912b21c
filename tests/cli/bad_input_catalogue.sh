#!/usr/bin/env bash
# The bad-input catalogue: hostile configs, scenes, traces and command lines. Each case must
# exit 2 with exactly one stderr line naming the file (and the key, line or element) and leave
# no output file, no temporary file and no staging directory. Resource cases: limits hit give
# a clear error (or, for a deep but valid hierarchy, a result) quickly, not a crash or a hang.
set -uo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
in="$tmp/in"; out="$tmp/out"
python3 "$src/tests/cli/make_bad_inputs.py" "$in" || { echo "FAIL: cannot make the inputs"; exit 1; }
pass=0; fail=0
bad() { echo "FAIL $*"; fail=$((fail+1)); }

# Nothing may be left: no $out, nothing new beside the inputs, no staging or temporary file.
leftovers() {
  [ -e "$out" ] && echo "$out"
  find "$tmp" \( -name '.rtusim-staging-*' -o -name '*.tmp-*' -o -name 'new*' \) -print
}

# expect_bad NAME PATTERN ARGS...: exit 2 within 60 s, one stderr line matching PATTERN.
expect_bad() {
  local name=$1 pattern=$2; shift 2
  rm -rf "$out"
  if [ "$1" = run ]; then shift; set -- "$rtusim" run "$@" --out "$out"; fi
  timeout 60 "$@" > "$tmp/stdout" 2> "$tmp/stderr"
  local rc=$? lines left
  # A sanitizer build's own reports (==PID== lines and their notes, e.g. ASan's once-a-process
  # note on SystemC's coroutine stacks when an error unwinds one) are not the run's output.
  lines=$(grep -v -e '^==[0-9]*==' -e '^False positive error reports' -e '^For details see' "$tmp/stderr" | wc -l)
  left=$(leftovers)
  if [ $rc -ne 2 ]; then bad "$name: exit $rc, want 2"; head -3 "$tmp/stderr"; return; fi
  if [ "$lines" -ne 1 ]; then bad "$name: $lines stderr lines, want 1"; head -3 "$tmp/stderr"; return; fi
  if ! grep -qE -- "$pattern" "$tmp/stderr"; then bad "$name: stderr lacks /$pattern/"; cat "$tmp/stderr"; return; fi
  if [ -n "$left" ]; then bad "$name: left behind: $left"; return; fi
  pass=$((pass+1))
}

cfg() { printf "$2" > "$in/$1"; }
scene_cfg() { printf '[scene]\npath = "%s"\n[image]\nwidth = 16\nheight = 16\n%b' "$1" "${2:-}" > "$in/$1.toml"; }
D="$src/configs/default.toml"

# ---- command line ----
expect_bad cli_unknown_subcommand "unknown subcommand 'frobnicate'" "$rtusim" frobnicate "$D"
expect_bad cli_no_subcommand 'subcommand' "$rtusim"
expect_bad cli_unknown_option 'unknown-flag|not expected' "$rtusim" run "$D" --unknown-flag
expect_bad cli_threads_zero "--threads: expected a whole number from 1 to 4096, got '0'" "$rtusim" run "$D" --threads 0
expect_bad cli_threads_word "--threads: expected a whole number from 1 to 4096, got 'abc'" "$rtusim" hits "$D" --threads abc --out "$tmp/new.bin"
expect_bad cli_trace_format "format" "$rtusim" trace "$D" --format xml --out "$tmp/new.din"
expect_bad cli_replay_no_trace 'trace' "$rtusim" replay
expect_bad cli_replay_directory "$in: is a directory" "$rtusim" replay "$in"
expect_bad cli_replay_missing "nope.bin: cannot open" "$rtusim" replay "$in/nope.bin"
mkdir -p "$in/adir"
expect_bad cli_hits_out_directory "adir: is a directory" "$rtusim" hits "$D" --out "$in/adir"
expect_bad cli_trace_out_directory "adir: is a directory" "$rtusim" trace "$D" --out "$in/adir"
expect_bad cli_trace_out_no_parent 'does not exist' "$rtusim" trace "$D" --out "$tmp/no/such/new.din"
expect_bad cli_hits_out_no_parent 'does not exist' "$rtusim" hits "$D" --out "$tmp/no/such/new.bin"
: > "$in/afile"
expect_bad cli_run_out_is_file "afile: exists and is not a directory" "$rtusim" run "$D" --out "$in/afile"
expect_bad cli_run_out_unwritable "rtusim-new-out: cannot make a directory in /proc" "$rtusim" run "$D" --out /proc/rtusim-new-out
expect_bad cli_replay_bad_set "l1.size" "$rtusim" replay "$in/good.bin" --set l1.size=1000
expect_bad cli_replay_unknown_key "l1.sizes" "$rtusim" replay "$in/good.bin" --set l1.sizes=8192

# ---- config ----
cfg unknown.toml '[image]\nwidth = 64\n[tracer]\nmax_dept = 3\n'
expect_bad cfg_unknown_key 'unknown.toml:4: tracer.max_dept: unknown key' run "$in/unknown.toml"
cfg type.toml '[image]\nwidth = "big"\n'
expect_bad cfg_wrong_type 'type.toml:2: image.width: expected an integer' run "$in/type.toml"
cfg range.toml '[image]\nheight = 0\n'
expect_bad cfg_out_of_range 'range.toml:2: image.height: must be between' run "$in/range.toml"
cfg syntax.toml '[image\n'
expect_bad cfg_toml_syntax 'syntax.toml:1' run "$in/syntax.toml"
cfg dup.toml '[image]\nwidth = 8\nwidth = 9\n'
expect_bad cfg_duplicate_key 'dup.toml' run "$in/dup.toml"
printf '[image]\nwidth = 8\x00\n' > "$in/nul.toml"
expect_bad cfg_nul_byte 'nul.toml' run "$in/nul.toml"
expect_bad cfg_missing 'nope.toml: config file not found' run "$in/nope.toml"
expect_bad cfg_directory 'adir: is a directory, not a config file' run "$in/adir"
expect_bad cfg_not_a_file '/dev/null: not a regular file' run /dev/null
expect_bad cfg_sweep_table 'study_sweep.toml:[0-9]+: sweep.* belongs in a sweep spec: run this file with `rtusim sweep`' run "$src/configs/study_sweep.toml"
expect_bad cfg_vcd_directory '^rtusim: --set sim.vcd=.*: sim.vcd: .*: is a directory' run "$D" --set sim.tier=cycle --set sim.vcd="$in/adir"
# A frame whose simulated time passes 2^44 cycles (one leaf of every triangle, a 2^20-cycle
# test interval): a clear error, not a crashed run (the unit's far events keep 44 bits of cycle).
expect_bad cycle_time_limit 'simulated time reached 2\^44 cycles' run "$D" --set sim.tier=cycle --set kdtree.max_depth=0 --set tracer.max_depth=0 --set isect.interval_cycles=1048576 --set image.width=64 --set image.height=64
# A DRAM row smaller than a line (each request is placed by its first byte); "full" ways over
# the ways' limit (a 1 GiB cache of 4-byte lines: it ran for minutes).
expect_bad cfg_row_below_line '^rtusim: --set dram.row_bytes=8: dram.row_bytes: 8 is smaller than a request' run "$D" --set sim.tier=cycle --set dram.row_bytes=8 --set dram.burst_length=1
# ... in the timed tiers only: the functional tier has no rows.
if "$rtusim" run "$D" --set image.width=8 --set image.height=8 --set l1.line=16384 --set l1.size=65536 --out "$out" > /dev/null 2>&1; then pass=$((pass+1)); else bad "functional_line_over_row: rejected"; fi
expect_bad cfg_full_ways_limit '^rtusim: --set l1.assoc=full: l1.assoc: 268435456 ways' run "$D" --set l1.assoc=full --set l1.size=1073741824 --set l1.line=4
# Several layouts: each layout's file (stem_<layout>) checked before any simulation (it failed
# after the first layout had run and left its complete VCD beside the directory).
mkdir -p "$in/lv_odfl.vcd"
expect_bad cfg_vcd_layout_directory '^rtusim: --set sim.vcd=.*: sim.vcd: .*lv_odfl.vcd: is a directory' run "$D" --set sim.tier=cycle --set sim.vcd="$in/lv.vcd" --set 'layout.kind=["dfl","odfl"]'
[ ! -e "$in/lv_dfl.vcd" ] || bad "cfg_vcd_layout_directory: lv_dfl.vcd written"
expect_bad cli_replay_key_list 'l1.mshrs: unknown key \(replay takes l1.size, l1.assoc, l1.line, l1.policy and l1.seed\)' "$rtusim" replay "$in/good.bin" --set l1.mshrs=3
expect_bad cli_trace_layouts_set '^rtusim: --set layout.kind=.*: layout.kind: trace takes one layout' "$rtusim" trace "$D" --set 'layout.kind=["dfl","odfl"]' --out "$tmp/new.din"
expect_bad cfg_set_value '--set tracer.max_depth=x' run "$D" --set tracer.max_depth=x
expect_bad cfg_set_no_equals 'tracer.max_depth' run "$D" --set tracer.max_depth
expect_bad cfg_set_unknown 'tracer.bogus' run "$D" --set tracer.bogus=1
expect_bad cfg_layout_unknown "layout.kind: unknown value 'zfl'" run "$D" --set layout.kind=zfl
expect_bad cfg_tier_unknown "sim.tier: unknown value 'gpu'" run "$D" --set sim.tier=gpu
expect_bad cfg_layout_twice "^rtusim: --set layout.kind=.*: layout.kind: 'dfl' is listed twice$" run "$D" --set 'layout.kind=["dfl","dfl"]'
expect_bad cfg_dram_burst_row '^rtusim: --set dram.bus_bytes=48: dram.bus_bytes: 48 x dram.burst_length 8 = 384 bytes per burst does not divide dram.row_bytes = 8192' run "$D" --set sim.tier=cycle --set dram.bus_bytes=48
expect_bad cfg_rays_in_flight_max 'sim.rays_in_flight: must be between 1 and 65536' run "$D" --set sim.tier=cycle --set sim.rays_in_flight=1048576
expect_bad cfg_dram_channels 'dram.channels: must be between' run "$D" --set sim.tier=cycle --set dram.channels=0
expect_bad cfg_l1_size 'l1.size' run "$D" --set l1.size=8000
expect_bad cfg_width_huge 'image.width' run "$D" --set image.width=100000000
expect_bad cfg_camera_eye_target 'camera.target: target equals eye' run "$D" --set 'camera.eye=[1,2,3]' --set 'camera.target=[1,2,3]'
printf '[camera]\neye = [1, 2, 3]\ntarget = [0, 0, 0]\n' > "$in/cam.toml"
expect_bad cfg_camera_set_origin '^rtusim: --set camera.target=\[1,2,3\]: camera.target: target equals eye' run "$in/cam.toml" --set 'camera.target=[1,2,3]'
expect_bad cfg_camera_one_key '^rtusim: --set camera.eye=.*: camera.eye: camera.eye and camera.target are both required' run "$D" --set 'camera.eye=[0.5,0.5,2]'
expect_bad cfg_camera_up_parallel 'configs/default.toml: camera.up: up is parallel' run "$D" --set 'camera.eye=[0,0,0]' --set 'camera.target=[0,5,0]'
expect_bad cfg_camera_up_zero '^rtusim: --set camera.up=\[0,0,0\]: camera.up: up is the zero vector' run "$D" --set 'camera.eye=[0,0,5]' --set 'camera.target=[0,0,0]' --set 'camera.up=[0,0,0]'
expect_bad cfg_camera_far '^rtusim: --set camera.eye=\[1e20,1,3\]: camera.eye: eye and target are too far apart for single precision' run "$D" --set 'camera.eye=[1e20,1,3]' --set 'camera.target=[0,1,0]'
expect_bad cfg_target_key_not_measured "^rtusim: --set sample.target_key=sim.cycles: sample.target_key: 'sim.cycles' is not measured by this tier" run "$D" --set sample.target_ci=0.1 --set sample.target_key=sim.cycles
expect_bad trace_interleaved '^rtusim: --set functional.rays_in_flight=4: functional.rays_in_flight: 4: trace records' "$rtusim" trace "$D" --set functional.rays_in_flight=4 --out "$tmp/t.din"
expect_bad trace_sampled '^rtusim: --set sample.rate=0.5: sample.rate: 0.5: trace records' "$rtusim" trace "$D" --set sample.rate=0.5 --out "$tmp/t.din"
expect_bad cfg_unknown_camera "scene.camera: no camera node 'nowhere'" run "$D" --set scene.camera=nowhere

# ---- scene ----
for case in count_2p62:'accessor 0 .*overrun' count_2p40:'accessor 0 .*overrun' \
            index_count_huge:'accessor 1 .*overrun' bad_index:'index 7 out of range' \
            view_range:'buffer view 9 out of range' view_overrun:'buffer view 0: bytes' \
            yfov_zero:'camera 0: yfov' yfov_negative:'camera 0: yfov' yfov_pi:'camera 0: yfov' \
            scale_zero:'node 0: transform is singular' matrix_zero:'node 0: transform is singular' \
            nan_positions:'element 0 is not a finite position' own_ancestor:'node 0 is its own ancestor' \
            child_range:'child 5 out of range' mesh_range:'mesh 3 out of range' \
            material_range:'material 4 out of range' no_position:'no POSITION' \
            int_positions:'non-float positions' index_float:'accessor 1 \(indices' \
            sparse:'sparse accessors' no_triangles:'no triangles' scene_range:'scene 4 out of range' \
            stride_small:'byteStride 4' deep_json:'nested deeper than' broken:'cannot parse glTF'; do
  name=${case%%:*}; pattern=${case#*:}
  scene_cfg "$name.gltf"
  expect_bad "scene_$name" "$name.gltf.toml:2: scene.path: .*$name.gltf: .*$pattern" run "$in/$name.gltf.toml"
done
for case in version1:'unsupported .glb version 1' version3:'unsupported .glb version 3' \
            truncated:'truncated .glb' badmagic:'not a .glb \(bad magic\)'; do
  name=${case%%:*}; pattern=${case#*:}
  scene_cfg "$name.glb"
  expect_bad "scene_glb_$name" "$name.glb: $pattern" run "$in/$name.glb.toml"
done
scene_cfg scene.obj
expect_bad scene_extension "scene.obj: unknown scene file extension" run "$in/scene.obj.toml"
scene_cfg missing.gltf
expect_bad scene_missing 'scene.path: .*missing.gltf' run "$in/missing.gltf.toml"
mkdir -p "$in/adir.gltf"
scene_cfg adir.gltf
expect_bad scene_directory 'adir.gltf: is a directory' run "$in/adir.gltf.toml"
printf '[scene]\npath = ""\n' > "$in/empty_path.toml"
expect_bad scene_empty_path 'scene path is empty' run "$in/empty_path.toml"
expect_bad scene_version1 "version1.gltf: asset.version '1.0': only glTF 2.x" run "$D" --set scene.path="$in/version1.gltf"
expect_bad scene_camera_ambiguous "scene.camera: 2 camera nodes are named 'A'" run "$D" --set scene.path="$in/dup_cameras.gltf" --set scene.camera=A
# $RTUSIM_SCENESX is a path of its own, not $RTUSIM_SCENES followed by X.
expect_bad scene_env_prefix 'RTUSIM_SCENESX/box/box.gltf: file not found' run "$D" --set 'scene.path="$RTUSIM_SCENESX/box/box.gltf"'
scene_cfg good.gltf '[camera]\neye = [0.2, 0.2, 1]\ntarget = [0.2, 0.2, 1]\n'
expect_bad scene_camera_eye_target 'good.gltf.toml:[0-9]*: camera.target: target equals eye' run "$in/good.gltf.toml"

# ---- trace ----
for case in bad_version:'unsupported bin trace version 7' node_zero:'node size 0 bytes' \
            node_huge:'node size 2147483647 bytes' layout_len0:'layout name length 0' \
            trailing:'2 bytes of trailing data' checksum:'checksum mismatch' \
            bad_varint:'bad varint in record 0' count_mismatch:'records cannot take|beyond the header' \
            payload_short:'truncated: payload has' truncated:'truncated' magic_prefix:'truncated' \
            empty:'empty file' garbage:'bad magic' \
            top_wrap:'record 2: a node of 8 bytes at 0xfffffffffffffffc runs past the top'; do
  name=${case%%:*}; pattern=${case#*:}
  expect_bad "trace_bin_$name" "$name.bin: (bad header: )?$pattern" "$rtusim" replay "$in/$name.bin"
done
for case in bad_label:'line 2: expected' nul:'line 2: .\\x00. is not a hex digit' \
            long_addr:'line 1: expected a hex address' size_zero:'line 1: access size 0' \
            size_huge:'line 1: access size 2147483647' after_size:'line 1: expected a hex size|line 1: unexpected' \
            long_line:'line 1: longer than' no_address:'line 2: expected' \
            top_wrap:'line 2: an access of 8 bytes at 0xfffffffffffffffc runs past the top'; do
  name=${case%%:*}; pattern=${case#*:}
  expect_bad "trace_din_$name" "$name.din: $pattern" "$rtusim" replay "$in/$name.din"
done

# ---- resource limits ----
scene_cfg big.gltf
RTUSIM_MAX_SCENE_MB=1 expect_bad limit_scene_file 'big.gltf: 2 MiB file, over the limit of 1 MiB' run "$in/big.gltf.toml"
scene_cfg good.gltf
RTUSIM_MAX_SCENE_MB=x expect_bad limit_bad_env 'RTUSIM_MAX_SCENE_MB' run "$in/good.gltf.toml"
# A 200,000-node chain is valid: loaded without a stack overflow, in bounded time.
scene_cfg deep_chain.gltf '[camera]\neye = [0.2, 0.2, 2]\ntarget = [0.2, 0.2, 0]\n'
if timeout 120 "$rtusim" run "$in/deep_chain.gltf.toml" --out "$out" > /dev/null 2> "$tmp/stderr" && [ -f "$out/stats.json" ]; then
  pass=$((pass+1))
else
  bad "limit_deep_chain: exit $?"; head -3 "$tmp/stderr"
fi
rm -rf "$out"
# Good inputs of each kind pass (the cases above fail for their defect only).
for f in good.bin good.din; do
  if "$rtusim" replay "$in/$f" > /dev/null 2>&1; then pass=$((pass+1)); else bad "good_$f: rejected"; fi
done
scene_cfg good.glb '[camera]\neye = [0.2, 0.2, 2]\ntarget = [0.2, 0.2, 0]\n'
if "$rtusim" run "$in/good.glb.toml" --out "$out" > /dev/null 2>&1; then pass=$((pass+1)); else bad "good_glb: rejected"; fi

echo "bad_input_catalogue: $pass passed, $fail failed"
[ $fail -eq 0 ] && [ $pass -ge 60 ]
