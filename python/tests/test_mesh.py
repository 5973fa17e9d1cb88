"""mvr.Mesh: meshes from numpy arrays render as the same mesh from a file, mixed with files,
placed, textured, with vertex colours; bad arrays raise ValueError naming the array."""
import numpy as np
import pytest

import mvr

# A unit cube as an OBJ writes it: 8 positions, 6 normals, quads with per-face normals.
CUBE_OBJ = """v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
vn 0 0 -1
vn 0 0 1
vn -1 0 0
vn 1 0 0
vn 0 -1 0
vn 0 1 0
f 1//1 4//1 3//1 2//1
f 5//2 6//2 7//2 8//2
f 1//3 5//3 8//3 4//3
f 2//4 3//4 7//4 6//4
f 1//5 2//5 6//5 5//5
f 4//6 8//6 7//6 3//6
"""


def cube_arrays():
    """The same cube as arrays: each face its own 4 vertices (a normal per face)."""
    positions = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                          [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=np.float64)
    faces = [([0, 3, 2, 1], [0, 0, -1]), ([4, 5, 6, 7], [0, 0, 1]), ([0, 4, 7, 3], [-1, 0, 0]),
             ([1, 2, 6, 5], [1, 0, 0]), ([0, 1, 5, 4], [0, -1, 0]), ([3, 7, 6, 2], [0, 1, 0])]
    vertices, normals, triangles = [], [], []
    for quad, n in faces:
        base = len(vertices)
        vertices += [positions[i] for i in quad]
        normals += [n] * 4
        triangles += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
    return np.array(vertices), np.array(triangles, dtype=np.int32), np.array(normals, float)


def test_a_numpy_mesh_renders_the_pixels_of_the_same_obj(tmp_path):
    obj = tmp_path / "cube.obj"
    obj.write_text(CUBE_OBJ)
    v, f, n = cube_arrays()
    mesh = mvr.Mesh(v, f, normals=n, name="cube")
    assert (mesh.vertex_count, mesh.triangle_count, mesh.name) == (24, 12, "cube")
    kw = dict(views=2, size=(96, 72), azimuth=30, elevation=20, shading="flat")
    from_file = mvr.render([obj], **kw)
    from_arrays = mvr.render(mesh, **kw)
    np.testing.assert_array_equal(from_arrays.color, from_file.color)
    assert from_arrays.scene == "cube"


def test_meshes_mix_with_files_and_are_placed(tmp_path):
    obj = tmp_path / "cube.obj"
    obj.write_text(CUBE_OBJ)
    v, f, n = cube_arrays()
    both = mvr.render([obj, mvr.Mesh(v, f, normals=n, placement="4,0,0,0.5")], views=1,
                      size=(96, 48))
    assert both.scene == f"{obj} + mesh"
    alone = mvr.render([obj], views=1, size=(96, 48))
    assert not np.array_equal(both.color, alone.color)  # the second cube is there


def test_a_textured_mesh_shows_its_texture():
    v = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
    f = np.array([[0, 1, 2], [0, 2, 3]])
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    red = np.zeros((4, 4, 3), np.uint8)
    red[..., 0] = 255
    r = mvr.render(mvr.Mesh(v, f, uvs=uv, texture=red), views=1, size=(64, 48), shading="flat")
    centre = r.color[0, 24, 32]
    assert centre[0] > 100 and centre[1] < 30 and centre[2] < 30, centre


@pytest.mark.parametrize("args,message", [
    (dict(vertices=np.zeros((4, 2)), faces=[[0, 1, 2]]), r"vertices: expected shape \(N, 3\), got \(4, 2\)"),
    (dict(vertices=[[0, 0, 0], [1, 0, 0], [0, np.nan, 0]], faces=[[0, 1, 2]]), "vertices: row 2 is not finite"),
    (dict(vertices=np.eye(3), faces=[[0, 1, 3]]), r"faces: row 0 has index 3 \(expected 0..2\)"),
    (dict(vertices=np.eye(3), faces=[[0.0, 1.0, 2.0]]), "faces: expected integers"),
    (dict(vertices=np.eye(3), faces=[[0, 1, 2]], normals=np.ones((2, 3))), "normals: 2 rows for 3 vertices"),
    (dict(vertices=np.eye(3), faces=[[0, 1, 2]], colors=np.ones((2, 3))), "colors: 2 rows for 3 vertices"),
    (dict(vertices=np.eye(3), faces=[[0, 1, 2]], colors=np.ones((3, 5))), r"colors: expected shape \(N, 3\) or \(N, 4\), got \(3, 5\)"),
    (dict(vertices=np.eye(3), faces=[[0, 1, 2]], colors=np.full((3, 3), 1.5)), r"colors: row 0 has 1.5 \(expected 0..1\)"),
    (dict(vertices=np.eye(3), faces=[[0, 1, 2]], colors=np.ones((3, 3), np.int64)), "colors: expected floats"),
    (dict(vertices=np.eye(3), faces=[[0, 1, 2]], texture=np.zeros((2, 2, 3), np.uint8)), "texture: needs uvs"),
])
def test_bad_arrays_name_the_array(args, message):
    with pytest.raises(ValueError, match=message):
        mvr.Mesh(**args)


def test_a_bad_placement_names_the_mesh():
    with pytest.raises(ValueError, match="model 'm@1,2': placement '1,2' has 2 numbers"):
        mvr.render(mvr.Mesh(np.eye(3), [[0, 1, 2]], name="m", placement="1,2"), views=1, size=(32, 24))


# ---- vertex colours ------------------------------------------------------------------------

QUAD_V = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
QUAD_F = np.array([[0, 1, 2], [0, 2, 3]])


def srgb_to_linear(c):
    c = np.asarray(c, np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


@pytest.mark.parametrize("shading", ["flat", "vertex", "pixel"])
def test_a_uniform_vertex_colour_scales_the_lit_white_mesh(shading):
    # Lit with white vertex colours the quad shows its lighting D (+ specular S); a colour c
    # gives c * D + S, so with c per channel the test predicts each pixel from the two renders
    # with no specular (flat) or compares channel ratios where the white render is unclamped.
    kw = dict(views=1, size=(64, 48), shading=shading)
    white = mvr.render(mvr.Mesh(QUAD_V, QUAD_F, colors=np.ones((4, 3))), **kw).color[0]
    c = np.array([0.5, 0.25, 1.0])
    tinted = mvr.render(mvr.Mesh(QUAD_V, QUAD_F, colors=np.tile(c, (4, 1))), **kw).color[0]
    centre = (24, 32)
    w = white[centre][:3].astype(float)
    t = tinted[centre][:3].astype(float)
    assert w.min() > 40 and w.max() < 250, w  # lit, not clamped: the prediction holds
    if shading == "flat":  # no specular: exactly c * D, quantized
        np.testing.assert_allclose(t, np.round(c * w), atol=1.5)
    else:  # c * D + S with S the same in both: the blue (c = 1) channel equals white's
        assert abs(t[2] - w[2]) <= 1
        assert t[0] < w[0] and t[1] < t[0], (t, w)


def test_vertex_colours_are_interpolated_across_the_quad():
    red, blue = [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]
    colors = np.array([red, blue, blue, red])  # left edge red, right edge blue
    r = mvr.render(mvr.Mesh(QUAD_V, QUAD_F, colors=colors), views=1, size=(96, 48),
                   shading="flat").color[0]
    row = r[24, :, :3].astype(int)
    covered = np.nonzero(row.sum(axis=1) != row[0].sum())[0]
    left, right = covered.min() + 2, covered.max() - 2
    assert row[left][0] > 5 * max(row[left][2], 1), row[left]    # red at the left edge
    assert row[right][2] > 5 * max(row[right][0], 1), row[right]  # blue at the right edge
    mid = (left + right) // 2
    # A quad facing the camera: screen-linear, so the middle is half of each (within a pixel).
    ratio = row[mid][0] / (row[mid][0] + row[mid][2])
    assert 0.4 < ratio < 0.6, row[mid]


def test_uint8_colours_are_srgb_and_floats_linear():
    kw = dict(views=1, size=(64, 48), shading="flat")
    b = np.array([[200, 100, 50]] * 4, np.uint8)
    from_bytes = mvr.render(mvr.Mesh(QUAD_V, QUAD_F, colors=b), **kw).color
    lin = srgb_to_linear(b / 255.0).astype(np.float32)
    from_floats = mvr.render(mvr.Mesh(QUAD_V, QUAD_F, colors=lin), **kw).color
    np.testing.assert_array_equal(from_bytes, from_floats)


@pytest.mark.parametrize("shading", ["flat", "vertex", "pixel"])
def test_vertex_coloured_unified_equals_multipass_and_gl_is_within_bound(shading):
    rng = np.random.default_rng(7)
    v, f, n = cube_arrays()
    colors = rng.uniform(0.0, 1.0, (len(v), 4))
    colors[:, 3] = 1.0
    mesh = mvr.Mesh(v, f, normals=n, colors=colors)
    kw = dict(views=5, size=(80, 60), azimuth=30, elevation=20, shading=shading)
    multipass = mvr.render(mesh, method="multipass", **kw).color
    unified = mvr.render(mesh, method="unified", **kw).color
    np.testing.assert_array_equal(unified, multipass)
    # Every exact gl method against soft within the conformance table's kGlVsSoft
    # (tests/conformance/tolerances.h): at most 1 % of the pixels more than 2/255 off.
    # Measured on llvmpipe and zink: max 1/255, on 0.2-0.3 % of the pixels (edges).
    drawn = 0
    for method in ("multipass", "gs-layered", "gs-invocations", "instanced-layer",
                   "viewport-array", "multiview", "kalaiah-emulation"):
        try:
            gl = mvr.render(mesh, backend="gl", method=method, **kw).color
        except (RuntimeError, ValueError) as e:  # a method this driver lacks, or no GL
            assert "not supported" in str(e) or "unavailable" in str(e), str(e)
            continue
        drawn += 1
        diff = np.abs(gl.astype(int) - multipass.astype(int)).max(axis=-1)
        assert (diff > 2).mean() <= 0.01, (method, (diff > 2).mean(), diff.max())
    if not drawn:
        pytest.skip("gl: no method draws here")


def test_obj_and_ply_vertex_colours_render_as_the_same_mesh_from_arrays(tmp_path):
    # OBJ's "v x y z r g b" (MeshLab, Blender) and PLY's uchar red/green/blue (scanners) are
    # sRGB: the same pixels as the uint8 array of the same colours.
    b = np.array([[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 51]], np.uint8)
    obj = tmp_path / "quad.obj"
    obj.write_text("".join(f"v {p[0]:g} {p[1]:g} {p[2]:g} {c[0] / 255:g} {c[1] / 255:g} "
                           f"{c[2] / 255:g}\n" for p, c in zip(QUAD_V, b)) + "f 1 2 3\nf 1 3 4\n")
    ply = tmp_path / "quad.ply"
    ply.write_text("ply\nformat ascii 1.0\ncomment written like MeshLab's\nelement vertex 4\n"
                   "property float x\nproperty float y\nproperty float z\n"
                   "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                   "element face 2\nproperty list uchar int vertex_indices\nend_header\n" +
                   "".join(f"{p[0]:g} {p[1]:g} {p[2]:g} {c[0]} {c[1]} {c[2]}\n"
                           for p, c in zip(QUAD_V, b)) + "3 0 1 2\n3 0 2 3\n")
    kw = dict(views=2, size=(64, 48), shading="vertex")
    arrays = mvr.render(mvr.Mesh(QUAD_V, QUAD_F, colors=b), **kw).color
    for path in (obj, ply):
        got = mvr.render([path], **kw).color
        np.testing.assert_array_equal(got, arrays, err_msg=str(path))


def _gltf_quad_with_colors(path, rgba16):
    """A quad as Blender's glTF exporter writes a coloured mesh: indexed, POSITION + NORMAL +
    COLOR_0 as normalized unsigned shorts (VEC4), a metallic-roughness material."""
    import base64
    import json
    import struct
    pos = struct.pack("<12f", *QUAD_V.ravel())
    nrm = struct.pack("<12f", *([0, 0, 1] * 4))
    col = struct.pack("<16H", *np.asarray(rgba16, np.uint16).ravel())
    idx = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    blob = pos + nrm + col + idx
    views = [(0, len(pos)), (len(pos), len(nrm)), (len(pos) + len(nrm), len(col)),
             (len(pos) + len(nrm) + len(col), len(idx))]
    doc = {
        "asset": {"version": "2.0", "generator": "Khronos glTF Blender I/O v3.6.28"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "Quad"}],
        "materials": [{"name": "Material", "pbrMetallicRoughness": {
            "baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 0.5}}],
        "meshes": [{"name": "Quad", "primitives": [{"attributes": {
            "POSITION": 0, "NORMAL": 1, "COLOR_0": 2}, "indices": 3, "material": 0}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-1, -1, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "normalized": True, "count": 4,
             "type": "VEC4"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in views],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(blob).decode()}],
    }
    path.write_text(json.dumps(doc))
    return path


def test_gltf_color_0_is_linear_and_multiplies_the_base_colour(tmp_path):
    white = _gltf_quad_with_colors(tmp_path / "white.gltf", [[65535] * 4] * 4)
    c = np.array([0.5, 0.25, 1.0])
    tinted = _gltf_quad_with_colors(tmp_path / "tinted.gltf",
                                    [list(np.round(c * 65535).astype(int)) + [65535]] * 4)
    kw = dict(views=2, size=(64, 48), shading="flat")
    w = mvr.render([white], **kw).color[:, 24, 32, :3].astype(float)
    t = mvr.render([tinted], **kw).color[:, 24, 32, :3].astype(float)
    assert (w.min() > 40) and (w.max() < 250), w
    # Linear: c * D, not the sRGB decode of c (which would give 0.21 / 0.05 of white).
    np.testing.assert_allclose(t, np.round(c * w), atol=1.5)
