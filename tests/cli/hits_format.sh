#!/usr/bin/env bash
# `rtusim hits`: the RTH1 file (header, t per pixel, triangle id per pixel, little endian).
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$rtusim" hits "$src/configs/default.toml" --set image.width=33 --set image.height=17 --out "$tmp/h.rth" > /dev/null
python3 - "$tmp/h.rth" <<'PY'
import math, struct, sys
data = open(sys.argv[1], "rb").read()
assert data[:4] == b"RTH1", data[:4]
w, h, zero = struct.unpack_from("<3I", data, 4)
assert (w, h, zero) == (33, 17, 0)
assert len(data) == 16 + 8 * w * h, len(data)
t = struct.unpack_from(f"<{w*h}f", data, 16)
ids = struct.unpack_from(f"<{w*h}i", data, 16 + 4 * w * h)
assert all((math.isinf(a) and b == -1) or (a > 0 and b >= 0) for a, b in zip(t, ids))
assert sum(b >= 0 for b in ids) > w * h // 2, "the default camera sees the room"
PY
# Same as `run`'s primary rays: the same config gives the same file twice.
"$rtusim" hits "$src/configs/default.toml" --set image.width=33 --set image.height=17 --out "$tmp/h2.rth" > /dev/null
cmp "$tmp/h.rth" "$tmp/h2.rth"

# Against an independent expectation: a 20x20 quad in the plane z = 0 (triangle 0 below the
# diagonal y = x, triangle 1 above) seen from z = 5; t and the id of every pixel follow from the
# contract's pinhole camera in closed form. A flipped image, shifted ids or wrong t fail.
python3 - "$tmp" <<'PY'
import base64, json, struct, sys
tmp = sys.argv[1]
pos = struct.pack("<18f", -10, -10, 0, 10, -10, 0, 10, 10, 0, -10, -10, 0, 10, 10, 0, -10, 10, 0)
doc = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
       "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
       "accessors": [{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3"}],
       "bufferViews": [{"buffer": 0, "byteLength": len(pos)}],
       "buffers": [{"byteLength": len(pos),
                    "uri": "data:application/octet-stream;base64," + base64.b64encode(pos).decode()}]}
open(f"{tmp}/quad.gltf", "w").write(json.dumps(doc))
open(f"{tmp}/quad.toml", "w").write('[scene]\npath = "quad.gltf"\n[image]\nwidth = 40\nheight = 30\n'
                                    '[camera]\neye = [0.5, -0.25, 5]\ntarget = [0.5, -0.25, 0]\n'
                                    'up = [0, 1, 0]\nvfov = 60\n')
PY
"$rtusim" hits "$tmp/quad.toml" --out "$tmp/q.rth" > /dev/null
python3 - "$tmp/q.rth" <<'PY'
import math, struct, sys
data = open(sys.argv[1], "rb").read()
w, h = struct.unpack_from("<2I", data, 4)
t = struct.unpack_from(f"<{w*h}f", data, 16)
ids = struct.unpack_from(f"<{w*h}i", data, 16 + 4 * w * h)
eye, th, aspect = (0.5, -0.25, 5.0), math.tan(math.radians(60) / 2), w / h
checked = 0
for y in range(h):
    for x in range(w):
        sx = (2 * (x + 0.5) / w - 1) * th * aspect
        sy = (1 - 2 * (y + 0.5) / h) * th
        d = (sx, sy, -1.0)  # f = -z, r = +x, u = +y
        n = math.sqrt(sum(c * c for c in d))
        te = eye[2] / (-d[2] / n)
        px, py = eye[0] + te * d[0] / n, eye[1] + te * d[1] / n
        i = y * w + x
        assert abs(t[i] - te) <= 1e-5 * te, (x, y, t[i], te)
        if abs(px - py) > 1e-3:
            assert ids[i] == (0 if py < px else 1), (x, y, ids[i], px, py)
            checked += 1
assert checked > w * h * 0.9, checked
PY
echo "hits_format: 1 passed, 0 failed"
