#!/usr/bin/env bash
# Remakes the seed corpora in tests/fuzz/corpus/ (committed; run by hand, not by CI):
# small OBJ / PLY / glTF / GLB files cut from the shared models, PNGs of every color type,
# and JPEG / JPS / MPO files written by mvr itself. Usage: make_seeds.sh MVR_BINARY [SHARED_DIR]
set -euo pipefail
mvr=$(realpath "$1")
shared=$(realpath "${2:-$(dirname "$0")/../../../shared}")
cd "$(dirname "$0")"
# Only the folders made here: scene_gltf, scene_glb, mtl_reader and environment seeds were
# written by hand (environment: tests/fuzz/corpus/environment, RGBE by a few lines of Python).
rm -rf corpus/{obj,mtl,ply,gltf,glb,png,jpeg,mpo,jps,visual_json,sky,camera_path}
mkdir -p corpus/{obj,mtl,ply,gltf,glb,png,jpeg,mpo,jps,visual_json}

python3 - "$shared/models" <<'EOF'
import base64, json, struct, sys, zlib, os

models = sys.argv[1]

def obj_subset(path, faces_wanted):
    """The first faces_wanted faces of an OBJ with only the v/vt/vn they use, renumbered."""
    v, vt, vn, faces = [], [], [], []
    for line in open(path, errors="replace"):
        w = line.split()
        if not w: continue
        if w[0] == "v": v.append(w[1:4])
        elif w[0] == "vt": vt.append(w[1:3])
        elif w[0] == "vn": vn.append(w[1:4])
        elif w[0] == "f" and len(faces) < faces_wanted: faces.append(w[1:])
    maps = [{}, {}, {}]
    out_faces = []
    for f in faces:
        refs = []
        for corner in f:
            parts = corner.split("/")
            new = []
            for k, p in enumerate(parts):
                if not p: new.append(""); continue
                i = int(p); i = i - 1 if i > 0 else len((v, vt, vn)[k]) + i
                new.append(str(maps[k].setdefault(i, len(maps[k]) + 1)))
            refs.append("/".join(new))
        out_faces.append(refs)
    lines = []
    for k, (tag, src) in enumerate((("v", v), ("vt", vt), ("vn", vn))):
        for i, _ in sorted(maps[k].items(), key=lambda kv: kv[1]):
            lines.append(tag + " " + " ".join(src[i]))
    lines += ["f " + " ".join(r) for r in out_faces]
    return "\n".join(lines) + "\n", [[float(x) for x in v[i]] for i, _ in sorted(maps[0].items(), key=lambda kv: kv[1])], [[int(c.split("/")[0]) - 1 for c in r] for r in out_faces]

def put(kind, name, data):
    with open(os.path.join("corpus", kind, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())

meshes = {}
for m in ("suzanne", "spot", "teapot", "stanford-bunny"):
    text, pos, tris = obj_subset(os.path.join(models, m + ".obj"), 12)
    put("obj", m + "-12faces.obj", text)
    meshes[m] = (pos, [t[:3] for t in tris])
put("obj", "cube-quads.obj", "# a unit cube, quads, no normals\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n"
    "v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n")
put("obj", "relative-crlf-groups.obj", "mtllib m.mtl\r\no tri\r\ng a b\r\nv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nv 1 1 0\r\n"
    "vt 0 0\r\nvn 0 0 1\r\ns 1\r\nusemtl red\r\nf -4/1/1 -3/1/1 -2/1/1\r\nf 2//1 4//1 \\\r\n 3//1\r\nl 1 2\r\np 3\r\n")
put("mtl", "two.mtl", "# two materials\nnewmtl red\nKa 0.1 0 0\nKd 1 0 0\nKs 0.5 0.5 0.5\nNs 32\nd 1\nillum 2\n"
    "map_Kd -s 1 1 1 red.png\nnewmtl blue\nKd 0 0 1\nTr 0.5\nmap_Bump -bm 0.5 bump.png\nNi 1.45\nTf 1 1 1\n")
put("mtl", "pbr.mtl", "newmtl red\nPr 0.5\nPm 1\nPs 0.2\nPc 0.1\nPcr 0.3\nKe 1 1 0\naniso 0.1\nnorm n.png\nrefl -type sphere r.png\n")

# PLY: the suzanne subset in ascii, both binary orders (with normals / colors / extra
# properties), a face list with int counts, and tristrips with -1 restarts.
pos, tris = meshes["suzanne"]
def ply_header(fmt, nv, vprops, felem):
    h = ["ply", "format %s 1.0" % fmt, "comment from suzanne.obj", "element vertex %d" % nv]
    h += ["property %s %s" % p for p in vprops]
    h += felem + ["end_header"]
    return ("\n".join(h) + "\n").encode()
put("ply", "suzanne-ascii.ply", ply_header("ascii", len(pos), [("float", "x"), ("float", "y"), ("float", "z")],
    ["element face %d" % len(tris), "property list uchar int vertex_indices"]) +
    "".join("%g %g %g\n" % tuple(p) for p in pos).encode() + "".join("3 %d %d %d\n" % tuple(t) for t in tris).encode())
for fmt, e in (("binary_little_endian", "<"), ("binary_big_endian", ">")):
    body = b"".join(struct.pack(e + "3f3fBBB", *p, 0, 0, 1, 200, 100, 50) for p in pos)
    body += b"".join(struct.pack(e + "Bi3I", 3, 7, *t)[:1] + struct.pack(e + "3I", *t) + struct.pack(e + "i", 7) for t in tris)
    put("ply", "suzanne-%s.ply" % fmt, ply_header(fmt, len(pos), [("float", "x"), ("float", "y"), ("float", "z"),
        ("float", "nx"), ("float", "ny"), ("float", "nz"), ("uchar", "red"), ("uchar", "green"), ("uchar", "blue")],
        ["element face %d" % len(tris), "property list uchar uint vertex_indices", "property int flags"]) + body)
put("ply", "quad-int-counts.ply", "ply\r\nformat ascii 1.0\r\nelement vertex 4\r\nproperty double x\r\nproperty double y\r\n"
    "property double z\r\nelement face 1\r\nproperty list int int vertex_index\r\nend_header\r\n0 0 0\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n4 0 1 2 3\r\n")
put("ply", "tristrips.ply", "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
    "element tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 1 0\n7 0 1 2 3 -1 1 4\n")

# glTF / GLB: the spot subset as one indexed primitive (uint16), plus a second, non-indexed
# primitive with normals, under a node with a transform, buffers as a data URI / GLB chunk.
pos, tris = meshes["spot"]
ib = b"".join(struct.pack("<3H", *t) for t in tris)
ib += b"\0" * (-len(ib) % 4)
vb = b"".join(struct.pack("<3f", *p) for p in pos)
tri = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<9f", *([0, 0, 1] * 3))
blob = ib + vb + tri
lo = [min(p[k] for p in pos) for k in range(3)]; hi = [max(p[k] for p in pos) for k in range(3)]
def gltf(uri):
    buf = {"byteLength": len(blob)}
    if uri: buf["uri"] = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    return {
        "asset": {"version": "2.0", "generator": "mvr make_seeds.sh"},
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"children": [1], "rotation": [0, 0.7071068, 0, 0.7071068]}, {"mesh": 0, "translation": [1, 0, 0], "scale": [2, 2, 2]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 1}, "indices": 0, "mode": 4},
                                   {"attributes": {"POSITION": 2, "NORMAL": 3}}]}],
        "buffers": [buf],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(ib), "target": 34963},
                        {"buffer": 0, "byteOffset": len(ib), "byteLength": len(vb), "target": 34962},
                        {"buffer": 0, "byteOffset": len(ib) + len(vb), "byteLength": len(tri)}],
        "accessors": [{"bufferView": 0, "componentType": 5123, "count": 3 * len(tris), "type": "SCALAR"},
                      {"bufferView": 1, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
                      {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 2, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"}],
    }
put("gltf", "spot-12faces.gltf", json.dumps(gltf(True), indent=1))
j = json.dumps(gltf(False)).encode(); j += b" " * (-len(j) % 4)
glb = struct.pack("<II", len(j), 0x4E4F534A) + j + struct.pack("<II", len(blob), 0x004E4942) + blob
put("glb", "spot-12faces.glb", struct.pack("<III", 0x46546C67, 2, 12 + len(glb)) + glb)

# PNG: every color type and a 16-bit and a palette+tRNS and an interlaced one (1x1: Adam7's
# first pass holds the only pixel, so its data is one scanline).
def png(w, h, ctype, depth, rows, extra=b"", interlace=0):
    def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    raw = b"".join(b"\0" + r for r in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, depth, ctype, 0, 0, interlace))
            + extra + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
put("png", "rgba8-4x3.png", png(4, 3, 6, 8, [bytes(range(r * 16, r * 16 + 16)) for r in range(3)]))
put("png", "rgb8-3x2.png", png(3, 2, 2, 8, [bytes([255, 0, 0, 0, 255, 0, 0, 0, 255])] * 2, chunk(b"gAMA", struct.pack(">I", 45455))))
put("png", "gray8-4x2.png", png(4, 2, 0, 8, [b"\x00\x40\x80\xff"] * 2))
put("png", "gray16-2x2.png", png(2, 2, 0, 16, [b"\x00\x00\xff\xff", b"\x80\x00\x12\x34"]))
put("png", "gray-alpha8-2x1.png", png(2, 1, 4, 8, [b"\x10\x80\xf0\xff"]))
put("png", "rgba16-1x1.png", png(1, 1, 6, 16, [b"\x01\x02\x03\x04\x05\x06\xff\xff"]))
put("png", "palette2-4x1-trns.png", png(4, 1, 3, 2, [b"\x1b"], chunk(b"PLTE", b"\xff\x00\x00\x00\xff\x00\x00\x00\xff\xff\xff\xff") + chunk(b"tRNS", b"\x80")))
put("png", "gray1-8x1.png", png(8, 1, 0, 1, [b"\xa5"]))
put("png", "interlaced-1x1.png", png(1, 1, 2, 8, [b"\x11\x22\x33"], interlace=1))

calib = {"configVersion": "3.0", "serial": "LKG-P0000", "pitch": {"value": 52.59267044067383},
         "slope": {"value": -7.083540916442871}, "center": {"value": 0.8167931437492371},
         "viewCone": {"value": 40.0}, "invView": {"value": 1.0}, "verticalAngle": {"value": 0.0},
         "DPI": {"value": 324.0}, "screenW": {"value": 16.0}, "screenH": {"value": 12.0},
         "flipImageX": {"value": 0.0}, "flipImageY": {"value": 1.0}, "flipSubp": {"value": 1.0}}
put("visual_json", "portrait.json", json.dumps(calib, indent=4))
put("visual_json", "plain-numbers.json", '{"pitch": 40, "slope": 5.5, "center": 0.1, "DPI": 300, "flipSubp": true, "screenW": 0}')
put("visual_json", "nested.json", '{"a": [1, {"b": "pitch"}], "pitch": {"value": 4e1}, "slope": -1E0, "center": {"value": -0.5}, "DPI": {"value": 1e2}, "s": "\\"\\\\ \\u00e9"}')
EOF

# JPEG / JPS / MPO written by mvr: two 16x12 views of the default scene (and a 3-view MPO).
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$mvr" render -q --size 16x12 --views 2 -o "$tmp/two" --format jps --format mpo
"$mvr" render -q --size 16x12 --views 3 -o "$tmp/three" --format mpo
"$mvr" compose -q -f tb-half -o "$tmp/v.jpg" --jpeg-quality 60 "$tmp/two/view-0.png" "$tmp/two/view-1.png"
cp "$tmp/v.jpg" corpus/jpeg/view-16x12-q60.jpg
cp "$tmp/two/jps.jps" corpus/jps/two-16x12.jps
cp "$tmp/two/jps.jps" corpus/jpeg/jps-32x12.jpg
cp "$tmp/two/mpo.mpo" corpus/mpo/two-16x12.mpo
cp "$tmp/three/mpo.mpo" corpus/mpo/three-16x12.mpo
cp "$tmp/v.jpg" corpus/mpo/plain.jpg
cp "$tmp/two/view-1.png" corpus/png/mvr-view-16x12.png
cp "$tmp/two/view-1.png" corpus/jps/a-png.png

# --sky maps (stb_image): 2:1 equirectangular and 4:3 cube-cross PNGs and JPEGs (4:2:0, 4:4:4).
mkdir -p corpus/sky corpus/camera_path
sky() { ffmpeg -v error -f lavfi -i "gradients=s=$1:seed=$2" -frames:v 1 "${@:4}" -y "corpus/sky/$3"; }
sky 16x8 1 equirect-16x8.png
sky 16x12 2 cross-16x12.png -pix_fmt rgb24
sky 32x16 3 equirect-32x16.jpg -q:v 8
sky 16x12 4 cross-gray-16x12.png -pix_fmt gray
sky 16x12 5 cross-444-16x12.jpg -pix_fmt yuvj444p -q:v 10
# --camera-path keyframe files (docs/animation.md): the docs' example, a bare array, fov at
# every key, and times out of order (refused).
cat >corpus/camera_path/doc-example.json <<'JSON'
{"keys": [
  {"time": 0, "position": [0, 0, 6], "target": [0, 0, 0], "fov": 40},
  {"time": 2, "position": [4, 1, 4], "target": [0, 0.5, 0]}
]}
JSON
printf '[{"time": 0.5, "position": [1e-3, -2, 3.5e1], "target": [0, 0, 0]}]\n' \
    >corpus/camera_path/bare-array-one-key.json
printf '{"keys": [{"time": -1, "position": [0, 0, 6], "target": [0, 0, 0], "fov": 10},\n {"time": 0, "position": [6, 0, 0], "target": [0, 1, 0], "fov": 90},\n {"time": 0.25, "position": [0, 6, 0.1], "target": [0, 0, 0], "fov": 179.5},\n {"time": 10, "position": [-6, 0, 0], "target": [1, 1, 1]}], "comment": "\\u00e9 \\"quoted\\""}\n' \
    >corpus/camera_path/four-keys.json
printf '{"keys": [{"time": 1, "position": [0, 0, 6], "target": [0, 0, 0]}, {"time": 0.5, "position": [0, 0, 6], "target": [0, 0, 0]}]}\n' \
    >corpus/camera_path/times-out-of-order.json
du -sh corpus/*
