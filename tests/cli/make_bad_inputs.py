"""Writes the hostile scene and trace files of tests/cli/bad_input_catalogue.sh into DIR.

usage: make_bad_inputs.py DIR
Each file is the smallest input that shows one defect; the formats are those of the glTF 2.0
spec and of sim/trace/trace_format.h.
"""
import base64
import json
import struct
import sys
from pathlib import Path

out = Path(sys.argv[1])
out.mkdir(parents=True, exist_ok=True)
POS = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
IDX = struct.pack("<3H", 0, 1, 2) + b"\0\0"


def uri(data):
    return "data:application/octet-stream;base64," + base64.b64encode(data).decode()


def gltf(name, edit=None, buf=POS + IDX, text=None):
    d = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
         "nodes": [{"mesh": 0}],
         "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                       {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
         "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                         {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
         "buffers": [{"byteLength": len(buf), "uri": uri(buf)}]}
    if edit:
        edit(d)
    (out / name).write_text(text if text is not None else json.dumps(d))


def setp(path, value):
    def edit(d):
        obj = d
        for k in path[:-1]:
            obj = obj[k]
        obj[path[-1]] = value
    return edit


def camera(yfov):
    def edit(d):
        d["nodes"].append({"camera": 0})
        d["scenes"][0]["nodes"].append(1)
        d["cameras"] = [{"type": "perspective", "perspective": {"yfov": yfov, "znear": 0.1}}]
    return edit


gltf("good.gltf")
gltf("count_2p62.gltf", setp(["accessors", 0, "count"], 2**62))
gltf("count_2p40.gltf", setp(["accessors", 0, "count"], 2**40))
gltf("index_count_huge.gltf", setp(["accessors", 1, "count"], 2**61))
gltf("bad_index.gltf", buf=POS + struct.pack("<3H", 0, 1, 7) + b"\0\0")
gltf("view_range.gltf", setp(["accessors", 0, "bufferView"], 9))
gltf("view_overrun.gltf", setp(["bufferViews", 0, "byteLength"], 4000))
gltf("yfov_zero.gltf", camera(0.0))
gltf("yfov_negative.gltf", camera(-0.5))
gltf("yfov_pi.gltf", camera(3.5))
gltf("scale_zero.gltf", setp(["nodes", 0, "scale"], [1, 0, 1]))
gltf("matrix_zero.gltf", setp(["nodes", 0, "matrix"], [0] * 16))
nan = struct.pack("<f", float("nan"))
gltf("nan_positions.gltf", buf=nan * 9 + IDX)
gltf("own_ancestor.gltf", setp(["nodes", 0, "children"], [0]))
gltf("version1.gltf", setp(["asset", "version"], "1.0"))


def two_cameras_named_a(d):
    camera(0.5)(d)
    d["nodes"][1]["name"] = "A"
    d["nodes"].append({"camera": 0, "name": "A", "translation": [0, 0, 3]})
    d["scenes"][0]["nodes"].append(2)


gltf("dup_cameras.gltf", two_cameras_named_a)
gltf("child_range.gltf", setp(["nodes", 0, "children"], [5]))
gltf("mesh_range.gltf", setp(["nodes", 0, "mesh"], 3))
gltf("material_range.gltf", setp(["meshes", 0, "primitives", 0, "material"], 4))
gltf("no_position.gltf", setp(["meshes", 0, "primitives", 0, "attributes"], {}))
gltf("int_positions.gltf", setp(["accessors", 0, "componentType"], 5123))
gltf("index_float.gltf", setp(["accessors", 1, "componentType"], 5126))
gltf("sparse.gltf", setp(["accessors", 0, "sparse"],
                         {"count": 1, "indices": {"bufferView": 1, "componentType": 5123},
                          "values": {"bufferView": 0}}))
gltf("no_triangles.gltf", setp(["meshes", 0, "primitives", 0, "mode"], 1))
gltf("scene_range.gltf", setp(["scene"], 4))
gltf("stride_small.gltf", setp(["bufferViews", 0, "byteStride"], 4))
gltf("deep_json.gltf", text='{"asset":{"version":"2.0","extras":' + "[" * 100000 + "]" * 100000 + "}}")
gltf("broken.gltf", text='{ "asset": {"version": "2.0"}, "meshes": [ ')
gltf("big.gltf", text=json.dumps({"asset": {"version": "2.0"}}) + " " * (2 << 20))
(out / "scene.obj").write_text("v 0 0 0\n")


# A deep but valid hierarchy: 200,000 nodes in a chain, the mesh at the bottom.
def chain(d):
    n = 200000
    d["nodes"] = [{"children": [i + 1]} for i in range(n - 1)] + [{"mesh": 0}]
gltf("deep_chain.gltf", chain)


def glb(name, version=2, magic=b"glTF", cut=None):
    d = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
         "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
         "bufferViews": [{"buffer": 0, "byteLength": 36}], "buffers": [{"byteLength": 36}]}
    j = json.dumps(d).encode()
    j += b" " * (-len(j) % 4)
    body = struct.pack("<II", len(j), 0x4E4F534A) + j + struct.pack("<II", 36, 0x004E4942) + POS
    data = magic + struct.pack("<II", version, 12 + len(body)) + body
    (out / name).write_bytes(data[:cut] if cut else data)


glb("good.glb")
glb("version1.glb", version=1)
glb("version3.glb", version=3)
glb("truncated.glb", cut=16)
glb("badmagic.glb", magic=b"gLtF")


def zigzag(d):
    d &= (1 << 64) - 1
    return ((d << 1) ^ (-(d >> 63) & ((1 << 64) - 1))) & ((1 << 64) - 1)


def varint(z):
    b = bytearray()
    while z >= 0x80:
        b.append((z & 0x7F) | 0x80)
        z >>= 7
    b.append(z)
    return bytes(b)


def checksum(addrs):
    h = 0xCBF29CE484222325
    for a in addrs:
        h = ((h ^ a) * 0x100000001B3) & ((1 << 64) - 1)
    return h


def bin_trace(name, addrs=(0, 8, 16, 4096), node=8, version=1, layout=b"dfl", count=None,
              cks=None, payload=None, extra=b"", payload_bytes=None, magic=b"RTUTRACE"):
    if payload is None:
        payload, prev = b"", 0
        for a in addrs:
            payload += varint(zigzag(a - prev))
            prev = a
    head = magic + struct.pack("<IIQQQQI", version, node, 0x1234,
                               len(addrs) if count is None else count,
                               checksum(addrs) if cks is None else cks,
                               len(payload) if payload_bytes is None else payload_bytes,
                               len(layout))
    (out / name).write_bytes(head + layout + payload + extra)


bin_trace("good.bin")
bin_trace("bad_version.bin", version=7)
bin_trace("node_zero.bin", node=0)
bin_trace("node_huge.bin", node=0x7FFFFFFF)
bin_trace("layout_len0.bin", layout=b"")
bin_trace("trailing.bin", extra=b"\x10\x10")
bin_trace("checksum.bin", cks=0xDEADBEEF)
bin_trace("bad_varint.bin", addrs=(0,), payload=b"\xff" * 10, count=1, payload_bytes=10)
bin_trace("count_mismatch.bin", count=1)
bin_trace("top_wrap.bin", addrs=(0, 8, (1 << 64) - 4))
bin_trace("payload_short.bin", payload_bytes=100)
(out / "truncated.bin").write_bytes(b"RTUTRACE\x01\x00")
(out / "magic_prefix.bin").write_bytes(b"RTUT")
(out / "empty.bin").write_bytes(b"")
(out / "garbage.bin").write_bytes(b"\x89PNG\r\n\x1a\n")
(out / "good.din").write_text("0 1000\n0 1008 8\n2 0x40\n")
(out / "bad_label.din").write_text("0 10\n7 20\n")
(out / "nul.din").write_bytes(b"0 10\n0 2\x003\n")
(out / "long_addr.din").write_text("0 12345678901234567\n")
(out / "size_zero.din").write_text("0 10 0\n")
(out / "size_huge.din").write_text("0 10 7fffffff\n")
(out / "after_size.din").write_text("0 10 8 junk\n")
(out / "long_line.din").write_text("0 10" + " " * 5000 + "\n")
(out / "no_address.din").write_text("0 10\n1\n")
(out / "top_wrap.din").write_text("0 10 8\n0 fffffffffffffffc 8\n")
