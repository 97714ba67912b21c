#!/usr/bin/env bash
# `rtusim run` on the default config: outputs, contract stats keys, determinism.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
small=(--set image.width=48 --set image.height=40)

"$rtusim" run "$src/configs/default.toml" "${small[@]}" --out "$tmp/a" > "$tmp/a.txt"
"$rtusim" run "$src/configs/default.toml" "${small[@]}" --out "$tmp/b" > /dev/null
for f in stats.json config.toml image.png heatmap_dfl.png; do
  [ -s "$tmp/a/$f" ] || { echo "FAIL: missing $f"; exit 1; }
done
grep -q "rays" "$tmp/a.txt" || { echo "FAIL: no summary table"; exit 1; }
ls -A "$tmp/a" | grep -q staging && { echo "FAIL: staging directory left behind"; exit 1; }

python3 - "$tmp/a/stats.json" "$tmp/b/stats.json" "$tmp/a/config.toml" <<'PY'
import json, sys, tomllib
a, b = (json.load(open(p)) for p in sys.argv[1:3])
for k in ["rays.total", "rays.primary", "rays.shadow", "rays.reflection", "rays.refraction",
          "tree.nodes", "tree.bytes", "traversal.node_fetches", "l1.accesses", "l1.misses",
          "dram.bytes.nodes", "dram.bytes.lists", "dram.bytes.triangles", "dram.bytes.total",
          "run.seconds"]:
    assert k in a, f"missing stats key {k}"
assert a["rays.primary"] == 48 * 40, a["rays.primary"]
assert a["rays.total"] == sum(a[f"rays.{k}"] for k in ["primary", "shadow", "reflection", "refraction"])
assert a["rays.reflection"] > 0 and a["rays.refraction"] > 0
assert a["tree.bytes"] == 8 * a["tree.nodes"], "dfl nodes are 8 bytes"
assert a["l1.accesses"] == a["traversal.node_fetches"], "8-byte nodes never straddle a line"
assert a["dram.bytes.nodes"] == 64 * a["l1.misses"]
assert a["dram.bytes.total"] == a["dram.bytes.nodes"] + a["dram.bytes.lists"] + a["dram.bytes.triangles"]
# Determinism: identical except timings.
timing = lambda k: k.endswith("seconds") or k.endswith("per_second")
da = {k: v for k, v in a.items() if not timing(k)}
db = {k: v for k, v in b.items() if not timing(k)}
assert da == db, [k for k in da if da[k] != db.get(k)]
# The effective config holds the overrides and the defaults, and is valid TOML.
cfg = tomllib.load(open(sys.argv[3], "rb"))
assert cfg["image"]["width"] == 48 and cfg["tracer"]["max_depth"] == 4, cfg
PY
# The effective config holds every key's default (camera.up and camera.vfov only with a camera of
# the config's own: they would make one), and with a camera, those two too.
"$rtusim" keys --format json > "$tmp/keys.json"
"$rtusim" run "$src/configs/default.toml" "${small[@]}" --set 'camera.eye=[0,1,3]' \
  --set 'camera.target=[0,1,0]' --set image.png=false --out "$tmp/cam" > /dev/null
python3 - "$tmp/keys.json" "$tmp/a/config.toml" "$tmp/cam/config.toml" <<'PY'
import json, math, sys, tomllib
keys = json.load(open(sys.argv[1]))
def value(cfg, key):
    for part in key.split("."):
        if not isinstance(cfg, dict) or part not in cfg:
            return None
        cfg = cfg[part]
    return cfg
def same(a, b):
    if isinstance(a, list):
        return isinstance(b, list) and len(a) == len(b) and all(map(same, a, b))
    if isinstance(a, float) or isinstance(b, float):
        return isinstance(b, (int, float)) and math.isclose(a, b, rel_tol=1e-6)
    return a == b
for path, camera in ((sys.argv[2], False), (sys.argv[3], True)):
    cfg = tomllib.load(open(path, "rb"))
    for k in keys:
        key, default = k["key"], k["default"]
        if key in ("image.width", "image.height") or default is None:
            continue
        got = value(cfg, key)
        if key in ("camera.up", "camera.vfov") and not camera:
            assert got is None, (path, key, got)
            continue
        if camera and key == "image.png":
            continue
        assert got is not None and same(default, got), (path, key, default, got)
PY
# The effective config reproduces the run.
"$rtusim" run "$tmp/a/config.toml" --out "$tmp/c" > /dev/null
python3 - "$tmp/a/stats.json" "$tmp/c/stats.json" <<'PY'
import json, sys
a, c = (json.load(open(p)) for p in sys.argv[1:3])
assert a["traversal.node_fetches"] == c["traversal.node_fetches"] and a["rays.total"] == c["rays.total"]
PY
# Several layouts over the same rays: per-layout keys, identical rays, ODFL's node memory = DFL's.
"$rtusim" run "$src/configs/default.toml" "${small[@]}" --set 'layout.kind=["dfl","odfl","subtree"]' --out "$tmp/m" > /dev/null
for f in heatmap_dfl.png heatmap_odfl.png heatmap_subtree.png diff_odfl_dfl.png; do
  [ -s "$tmp/m/$f" ] || { echo "FAIL: missing $f"; exit 1; }
done
python3 - "$tmp/a/stats.json" "$tmp/m/stats.json" <<'PY'
import json, sys
a, m = (json.load(open(p)) for p in sys.argv[1:3])
assert m["rays.total"] == a["rays.total"]
assert m["layout.dfl.dram.bytes.nodes"] == a["dram.bytes.nodes"], "the first layout's run is the single run"
assert m["layout.odfl.tree.bytes"] == m["layout.dfl.tree.bytes"]
assert m["layout.subtree.tree.bytes"] > m["layout.dfl.tree.bytes"]
assert m["layout.odfl.traversal.node_fetches"] == m["layout.dfl.traversal.node_fetches"], "same visits"
PY
# The maps' content, not just their presence: decoded, each map is W x H, each heatmap has more
# than one colour, the difference map only white, red-ish (R = 255, G = B) or blue-ish
# (B = 255, R = G) pixels, and white exactly where the two heatmaps agree.
python3 - "$tmp/m" 48 40 <<'PY'
import struct, sys, zlib
d, W, H = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
def png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack_from(">I4s", data, pos)
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack_from(">IIBB", body)
            assert (depth, colour) == (8, 2), (depth, colour)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, rows, prev, stride = zlib.decompress(idat), [], bytearray(3 * w), 3 * w
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - 3] if i >= 3 else 0
            b, c = prev[i], prev[i - 3] if i >= 3 else 0
            pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)  # Paeth: |p-a|, |p-b|, |p-c|
            pr = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            line[i] = (line[i] + [0, a, b, (a + b) // 2, pr][f]) & 255
        rows.append([tuple(line[3 * x:3 * x + 3]) for x in range(w)])
        prev = line
    return w, h, rows
maps = {k: png(f"{d}/{k}.png") for k in ["heatmap_dfl", "heatmap_odfl", "diff_odfl_dfl", "image"]}
# The heatmaps carry their colour scale below the W x H map; the frame and the diff map are W x H.
for k, (w, h, _) in maps.items():
    if k.startswith("heatmap_"):
        assert w == W and h > H, (k, w, h)
    else:
        assert (w, h) == (W, H), (k, w, h)
for k in ["heatmap_dfl", "heatmap_odfl"]:
    assert len({p for row in maps[k][2][:H] for p in row}) > 5, f"{k}: (nearly) one colour"
white = 0
for y in range(H):
    for x in range(W):
        r, g, b = maps["diff_odfl_dfl"][2][y][x]
        assert (r == 255 and g == b) or (b == 255 and r == g), (x, y, r, g, b)
        same = maps["heatmap_dfl"][2][y][x] == maps["heatmap_odfl"][2][y][x]
        if (r, g, b) == (255, 255, 255):
            white += 1
            assert same, (x, y)
assert white < W * H, "ODFL and DFL differ somewhere"
PY
# sim.vcd in the functional tier: no file, and a note that says so (exit 0).
"$rtusim" run "$src/configs/default.toml" "${small[@]}" --set sim.vcd="$tmp/f.vcd" --out "$tmp/v" \
  > /dev/null 2> "$tmp/v.err"
[ ! -e "$tmp/f.vcd" ] && grep -q "sim.vcd ($tmp/f.vcd) is not written: the functional tier" "$tmp/v.err" \
  || { echo "FAIL: sim.vcd in the functional tier"; cat "$tmp/v.err"; exit 1; }
# camera.vfov alone: the scene camera's field of view (narrower: fewer pixels see the room's
# walls, so a different frame), kept in config.toml, which runs it again; camera.up alone is an
# error naming what a config camera needs.
"$rtusim" run "$src/configs/default.toml" "${small[@]}" --set camera.vfov=30 --out "$tmp/f30" > /dev/null
"$rtusim" run "$tmp/f30/config.toml" --out "$tmp/f30b" > /dev/null
python3 - "$tmp/a/stats.json" "$tmp/f30/stats.json" "$tmp/f30b/stats.json" "$tmp/f30/config.toml" <<'PY'
import json, sys, tomllib
a, f, g = (json.load(open(p)) for p in sys.argv[1:4])
assert f["traversal.node_fetches"] != a["traversal.node_fetches"], "camera.vfov alone changed nothing"
assert f["traversal.node_fetches"] == g["traversal.node_fetches"], "config.toml does not rerun it"
assert tomllib.load(open(sys.argv[4], "rb"))["camera"] == {"vfov": 30.0}
PY
set +e
"$rtusim" run "$src/configs/default.toml" "${small[@]}" --set 'camera.up=[0,1,0]' --out "$tmp/up" > /dev/null 2> "$tmp/up.err"
rc=$?
set -e
[ $rc -eq 2 ] && grep -q "camera.eye and camera.target are both required" "$tmp/up.err" && [ ! -e "$tmp/up" ] \
  || { echo "FAIL: camera.up alone: exit $rc: $(cat "$tmp/up.err")"; exit 1; }
echo "run_default: 1 passed, 0 failed"
