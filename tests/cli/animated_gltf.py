#!/usr/bin/env python3
"""Writes a small animated glTF 2.0 file for the sequence and MPI tests: a red cube "mover"
(translation LINEAR over 1 s) with a child "arm" (rotation STEP at 0.5 s) whose child "tip"
is a green cube one unit up, and a camera "cam" (translation LINEAR). Usage: animated_gltf.py OUT.gltf
(tests/core/gltf_anim_fixture.h is the C++ tests' twin of this file, with the same keys)."""
import base64
import json
import math
import struct
import sys

h = 0.3
pos = [(x, y, z) for x in (-h, h) for y in (-h, h) for z in (-h, h)]
faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
         (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
s45 = math.sqrt(0.5)
chunks = [
    struct.pack("<24f", *[c for p in pos for c in p]),          # 0 positions
    struct.pack("<36H", *[i for f in faces for i in f]),  # 1 indices
    struct.pack("<2f", 0, 1),                                  # 2 times
    struct.pack("<2f", 0, 0.5),                                # 3 step times
    struct.pack("<6f", -1, 0, 0, 1, 0, 0),                     # 4 mover
    struct.pack("<8f", 0, 0, 0, 1, 0, 0, s45, s45),            # 5 arm (90° about z)
    struct.pack("<6f", 0.5, 0, 8, -0.5, 0.3, 6),               # 6 camera
]
blob, views = b"", []
for c in chunks:
    views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(c)})
    blob += c
acc = [
    {"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
     "min": [-h] * 3, "max": [h] * 3},
    {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"},
    {"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
    {"bufferView": 3, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [0.5]},
    {"bufferView": 4, "componentType": 5126, "count": 2, "type": "VEC3"},
    {"bufferView": 5, "componentType": 5126, "count": 2, "type": "VEC4"},
    {"bufferView": 6, "componentType": 5126, "count": 2, "type": "VEC3"},
]
prim = lambda m: {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": m}]}
doc = {
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 3]}],
    "nodes": [{"name": "mover", "mesh": 0, "translation": [-1, 0, 0], "children": [1]},
              {"name": "arm", "children": [2]},
              {"name": "tip", "mesh": 1, "translation": [0, 1, 0]},
              {"name": "cam", "camera": 0, "translation": [0.5, 0, 8]}],
    "cameras": [{"type": "perspective",
                 "perspective": {"yfov": 0.8, "aspectRatio": 1.0, "znear": 0.1, "zfar": 100}}],
    "meshes": [prim(0), prim(1)],
    "materials": [{"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}},
                  {"name": "green", "pbrMetallicRoughness": {"baseColorFactor": [0, 1, 0, 1]}}],
    "animations": [{"name": "swing",
                    "samplers": [{"input": 2, "output": 4, "interpolation": "LINEAR"},
                                 {"input": 3, "output": 5, "interpolation": "STEP"},
                                 {"input": 2, "output": 6}],
                    "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}},
                                 {"sampler": 1, "target": {"node": 1, "path": "rotation"}},
                                 {"sampler": 2, "target": {"node": 3, "path": "translation"}}]}],
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," +
                 base64.b64encode(blob).decode()}],
    "bufferViews": views, "accessors": acc,
}
with open(sys.argv[1], "w") as f:
    json.dump(doc, f)
