"""Scenes from files (issue 14) through mvr.render(): a glTF camera, and fov= overriding it."""
import base64
import json
import math
import struct

import numpy as np

import mvr
from conftest import read_png


def _gltf_with_camera(path, yfov):
    """A triangle in z = 0 seen by a glTF camera at (0, 0, 3) whose yfov is `yfov` radians."""
    positions = struct.pack("<9f", -1, -1, 0, 1, -1, 0, 0, 1, 0)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 3]}],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": yfov, "znear": 0.1, "zfar": 50}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [-1, -1, 0], "max": [1, 1, 0]}],
        "bufferViews": [{"buffer": 0, "byteLength": len(positions)}],
        "buffers": [{"byteLength": len(positions),
                     "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(positions).decode()}],
    }
    path.write_text(json.dumps(doc))
    return path


def test_fov_keyword_overrides_the_file_camera(cli, tmp_path):
    model = _gltf_with_camera(tmp_path / "cam.gltf", 0.6)
    own = mvr.render(model, size=(64, 48), views=1)
    assert math.isclose(own.rig["fov"], math.degrees(0.6), rel_tol=1e-5)
    # fov= wins over the file's yfov, as --fov does on the command line ...
    wide = mvr.render(model, size=(64, 48), views=1, fov=70.0)
    assert math.isclose(wide.rig["fov"], 70.0, rel_tol=1e-6)
    cli("render", model, "--size", "64x48", "--views", "1", "--fov", "70", "-o", tmp_path)
    np.testing.assert_array_equal(wide.color[0], read_png(tmp_path / "view-0.png"))
    # ... and the camera is still the file's (at (0, 0, 3), not the bounds' framing).
    assert np.allclose(wide.rig["eyes"][0], (0, 0, 3), atol=1e-5)
    # A wider fov shows the same triangle smaller: fewer covered pixels.
    background = own.color[0][0, 0]
    covered = lambda img: int(np.any(img != background, axis=-1).sum())
    assert covered(wide.color[0]) < covered(own.color[0])
    # fov equal to the default 45 still counts as given.
    same = mvr.render(model, size=(64, 48), views=1, fov=45.0)
    assert math.isclose(same.rig["fov"], 45.0, rel_tol=1e-6)
