#!/usr/bin/env bash
# `rtusim trace` and the trace formats: din and bin of the default config (at 64x64) hold the
# same addresses (the bin decoded here by an independent Python reader of the documented format);
# the count is run's traversal.node_fetches; the bin reader rejects a truncated file, a flipped
# byte and a bad magic with exit 2 and one stderr line naming the file; replay of a bin trace
# matches run's l1.misses, also for 12-byte subtree nodes that straddle 32-byte lines.
set -uo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
pass=0; fail=0
ok() { pass=$((pass+1)); }
bad() { echo "FAIL $1"; fail=$((fail+1)); }
cfg=$src/configs/default.toml
small=(--set image.width=64 --set image.height=64 --set image.png=false --set image.heatmaps=false)

"$rtusim" trace "$cfg" "${small[@]}" --out "$tmp/t.din" > /dev/null || bad "trace din"
"$rtusim" trace "$cfg" "${small[@]}" --out "$tmp/t.bin" --format bin > /dev/null || bad "trace bin"
"$rtusim" trace "$cfg" "${small[@]}" --out "$tmp/t2.din" --format din > /dev/null || bad "trace din explicit"
"$rtusim" run "$cfg" "${small[@]}" --out "$tmp/run" > /dev/null || bad "run"
cmp -s "$tmp/t.din" "$tmp/t2.din" && ok || bad "din is the default format / deterministic"
ls "$tmp" | grep -q tmp- && bad "temp file left behind" || ok

if python3 - "$tmp/t.din" "$tmp/t.bin" "$tmp/run/stats.json" <<'PY'
import json, re, struct, sys
din_path, bin_path, stats_path = sys.argv[1:4]
lines = open(din_path).read().splitlines()
assert all(re.fullmatch(r"0 [0-9a-f]+", l) for l in lines), "din: every line '0 <lowercase hex>'"
din = [int(l.split()[1], 16) for l in lines]
data = open(bin_path, "rb").read()
assert data[:8] == b"RTUTRACE", data[:8]
version, node_bytes, scene_hash, count, checksum, payload, name_len = struct.unpack_from("<IIQQQQI", data, 8)
layout = data[52:52 + name_len].decode()
assert (version, node_bytes, layout) == (1, 8, "dfl"), (version, node_bytes, layout)
body = data[52 + name_len:]
assert len(body) == payload, (len(body), payload)
addrs, prev, z, shift = [], 0, 0, 0
M = (1 << 64) - 1
for b in body:
    z |= (b & 0x7f) << shift
    shift += 7
    if b & 0x80:
        continue
    d = (z >> 1) ^ (-(z & 1) & M)
    prev = (prev + d) & M
    addrs.append(prev)
    z, shift = 0, 0
assert shift == 0, "payload ends inside a record"
assert len(addrs) == count, (len(addrs), count)
h = 0xcbf29ce484222325
for a in addrs:
    h = ((h ^ a) * 0x100000001b3) & M
assert h == checksum, (hex(h), hex(checksum))
assert addrs == din, "din and bin hold different addresses"
stats = json.load(open(stats_path))
assert count == stats["traversal.node_fetches"], (count, stats["traversal.node_fetches"])
assert all(a % 8 == 0 and a < stats["tree.bytes"] for a in addrs), "node addresses inside the node region"
PY
then ok; else bad "din/bin/stats agreement"; fi

# Replay of the bin and the din trace: run's l1 numbers.
misses=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['l1.misses'])" "$tmp/run/stats.json")
for f in t.bin t.din; do
  "$rtusim" replay "$tmp/$f" > "$tmp/replay.txt" 2>&1
  grep -qE "^  misses +$misses$" "$tmp/replay.txt" && ok || { bad "replay $f: want $misses misses"; cat "$tmp/replay.txt"; }
done
# Subtree nodes are 12 bytes: with 32-byte lines some straddle two lines; the bin header's node
# size lets replay count both, as run does.
sub=(--set layout.kind=subtree --set l1.line=32 --set l1.size=4096 --set l1.assoc=2)
"$rtusim" trace "$cfg" "${small[@]}" "${sub[@]}" --out "$tmp/s.bin" --format bin > /dev/null || bad "trace subtree"
"$rtusim" run "$cfg" "${small[@]}" "${sub[@]}" --out "$tmp/srun" > /dev/null || bad "run subtree"
read -r sacc smiss < <(python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print(s['l1.accesses'], s['l1.misses'])" "$tmp/srun/stats.json")
"$rtusim" replay "$tmp/s.bin" --set l1.line=32 --set l1.size=4096 --set l1.assoc=2 > "$tmp/sreplay.txt" 2>&1
grep -qE "^  accesses +$sacc$" "$tmp/sreplay.txt" && grep -qE "^  misses +$smiss$" "$tmp/sreplay.txt" && ok ||
  { bad "replay subtree: want $sacc accesses, $smiss misses"; cat "$tmp/sreplay.txt"; }

# expect_bad NAME PATTERN ARGS...: exit 2, one stderr line matching PATTERN.
expect_bad() {
  local name=$1 pattern=$2; shift 2
  "$@" > /dev/null 2> "$tmp/stderr"
  local rc=$?
  if [ $rc -ne 2 ]; then bad "$name: exit $rc, want 2"; cat "$tmp/stderr"; return; fi
  if [ "$(wc -l < "$tmp/stderr")" -ne 1 ]; then bad "$name: not one stderr line"; cat "$tmp/stderr"; return; fi
  grep -qE -- "$pattern" "$tmp/stderr" && ok || { bad "$name: stderr lacks /$pattern/"; cat "$tmp/stderr"; }
}
size=$(stat -c %s "$tmp/t.bin")
head -c $((size - 5)) "$tmp/t.bin" > "$tmp/trunc.bin"
expect_bad truncated 'trunc.bin: truncated' "$rtusim" replay "$tmp/trunc.bin"
head -c 30 "$tmp/t.bin" > "$tmp/short.bin"
expect_bad truncated_header 'short.bin: truncated' "$rtusim" replay "$tmp/short.bin"
# Flip one bit of the last payload byte: still a well-formed varint, a different address.
python3 - "$tmp/t.bin" "$tmp/flip.bin" <<'PY'
import sys
d = bytearray(open(sys.argv[1], "rb").read()); d[-1] ^= 0x02; open(sys.argv[2], "wb").write(d)
PY
expect_bad flipped_byte 'flip.bin: checksum mismatch' "$rtusim" replay "$tmp/flip.bin"
{ printf 'XTUTRACE'; tail -c +9 "$tmp/t.bin"; } > "$tmp/magic.bin"
expect_bad bad_magic 'magic.bin: bad magic' "$rtusim" replay "$tmp/magic.bin"
printf '0 1f00\n0 zz\n' > "$tmp/bad.din"
expect_bad bad_din_line 'bad.din: line 2' "$rtusim" replay "$tmp/bad.din"
expect_bad missing_trace 'nope.bin: cannot open' "$rtusim" replay "$tmp/nope.bin"
expect_bad replay_bad_key 'l2.size: unknown key' "$rtusim" replay "$tmp/t.bin" --set l2.size=4096
expect_bad replay_bad_cache 'l1.size' "$rtusim" replay "$tmp/t.bin" --set l1.size=100

# trace takes one layout; failures leave no file.
expect_bad several_layouts 'layout.kind: trace takes one layout' \
  "$rtusim" trace "$cfg" "${small[@]}" --set 'layout.kind=["dfl","odfl"]' --out "$tmp/multi.din"
[ -e "$tmp/multi.din" ] && bad "several_layouts left a file" || ok
expect_bad bad_format 'format' "$rtusim" trace "$cfg" --out "$tmp/f.txt" --format csv
expect_bad trace_no_dir 'does not exist' "$rtusim" trace "$cfg" --out "$tmp/no/such/dir/t.din"
expect_bad trace_bad_key 'tracer.max_dept: unknown key' "$rtusim" trace "$cfg" --set tracer.max_dept=2 --out "$tmp/k.din"
[ -e "$tmp/k.din" ] && bad "bad key left a file" || ok

echo "trace_format: $pass passed, $fail failed"
[ $fail -eq 0 ]
