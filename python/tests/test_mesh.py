"""mvr.Mesh: meshes from numpy arrays render as the same mesh from a file, mixed with files,
placed, textured; bad arrays raise ValueError naming the array."""
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
    (dict(vertices=np.eye(3), faces=[[0, 1, 2]], colors=np.ones((3, 3))), "colors: per-vertex colours are not rendered yet"),
    (dict(vertices=np.eye(3), faces=[[0, 1, 2]], texture=np.zeros((2, 2, 3), np.uint8)), "texture: needs uvs"),
])
def test_bad_arrays_name_the_array(args, message):
    with pytest.raises(ValueError, match=message):
        mvr.Mesh(**args)


def test_a_bad_placement_names_the_mesh():
    with pytest.raises(ValueError, match="model 'm@1,2': placement '1,2' has 2 numbers"):
        mvr.render(mvr.Mesh(np.eye(3), [[0, 1, 2]], name="m", placement="1,2"), views=1, size=(32, 24))
