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
echo "hits_format: 1 passed, 0 failed"
