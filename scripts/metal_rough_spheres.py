#!/usr/bin/python3
"""Writes metal-rough-spheres.gltf: 5 x 5 spheres whose metallic factor grows left to right
(0 .. 1) and roughness top to bottom (0.05 .. 1), base colour (0.9, 0.6, 0.2), as the chart
in Khronos's MetalRoughSpheres sample. docs/metal-rough-spheres.png is

    python3 scripts/metal_rough_spheres.py /tmp/spheres.gltf
    mvr render /tmp/spheres.gltf --views 1 --size 480x360 --shading pixel -o out

--sun LUX adds a KHR_lights_punctual sun of that intensity (docs/tonemap-none-vs-khr-neutral.png:
--sun 3, rendered at 400x300 with --tonemap none and with the default, side by side).
"""
import base64
import json
import math
import struct
import sys


def sphere(nu=32, nv=16):
    pos, idx = [], []
    for j in range(nv + 1):
        th = math.pi * j / nv
        for i in range(nu + 1):
            ph = 2 * math.pi * i / nu
            pos += [math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph)]
    for j in range(nv):
        for i in range(nu):
            a = j * (nu + 1) + i
            b = a + nu + 1
            idx += [a, a + 1, b, a + 1, b + 1, b]
    return pos, idx


def main(path, sun=None):
    pos, idx = sphere()
    blob = struct.pack(f"{len(pos)}f", *pos) * 2 + struct.pack(f"{len(idx)}H", *idx)
    count = len(pos) // 3
    materials, meshes, nodes = [], [], []
    for r in range(5):
        for c in range(5):
            materials.append({"name": f"metallic {c / 4:g} roughness {0.05 + 0.95 * r / 4:g}",
                              "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.6, 0.2, 1],
                                                       "metallicFactor": c / 4,
                                                       "roughnessFactor": 0.05 + 0.95 * r / 4}})
            meshes.append({"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1},
                                           "indices": 2, "material": len(materials) - 1}]})
            nodes.append({"mesh": len(meshes) - 1, "translation": [(c - 2) * 2.3, (2 - r) * 2.3, 0]})
    doc = {
        "asset": {"version": "2.0", "generator": "mvr scripts/metal_rough_spheres.py"},
        "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes, "meshes": meshes, "materials": materials,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
             "min": [-1, -1, -1], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": len(idx), "type": "SCALAR"}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos) * 4},
            {"buffer": 0, "byteOffset": len(pos) * 4, "byteLength": len(pos) * 4},
            {"buffer": 0, "byteOffset": len(pos) * 8, "byteLength": len(idx) * 2}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(blob).decode()}],
    }
    if sun is not None:
        doc["extensionsUsed"] = ["KHR_lights_punctual"]
        doc["extensions"] = {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "intensity": sun, "color": [1, 0.95, 0.9]}]}}
        doc["nodes"].append({"name": "Sun", "rotation": [-0.3, 0.2, 0.0, 0.93],
                             "extensions": {"KHR_lights_punctual": {"light": 0}}})
        doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    with open(path, "w") as f:
        json.dump(doc, f)


if __name__ == "__main__":
    args = sys.argv[1:]
    sun = None
    if "--sun" in args:
        i = args.index("--sun")
        sun = float(args[i + 1])
        del args[i:i + 2]
    main(args[0] if args else "metal-rough-spheres.gltf", sun)
