"""The viewpoint keywords (azimuth=, elevation=, distance=, target=, camera_position=, look_at=,
up=, camera_matrix=, focal_length_mm=, sensor_width_mm=), background=, png_compression= and
write=, as the CLI's options."""
import math
import os

import numpy as np
import pytest

import mvr


def test_an_eye_a_matrix_and_a_numpy_matrix_are_the_same_camera():
    eye = mvr.render(views=1, size=(64, 48), camera_position=(0, 1, 8), look_at=(0, 1, 0))
    m = np.eye(4)
    m[:3, 3] = (0, 1, 8)
    as_array = mvr.render(views=1, size=(64, 48), camera_matrix=m)
    as_text = mvr.render(views=1, size=(64, 48), camera_matrix=" ".join(str(x) for x in m.ravel()))
    np.testing.assert_array_equal(eye.color, as_array.color)
    np.testing.assert_array_equal(eye.color, as_text.color)


def test_azimuth_changes_the_view_and_zero_is_the_default_framing():
    default = mvr.render(views=1, size=(64, 48))
    zero = mvr.render(views=1, size=(64, 48), azimuth=0, elevation=0, distance="auto")
    side = mvr.render(views=1, size=(64, 48), azimuth=90)
    assert not np.array_equal(default.color, side.color)
    # The default scene has a viewpoint of its own: azimuth 0 frames the bounds from +Z.
    assert zero.color.shape == default.color.shape


def test_focal_length_sets_the_field_of_view():
    r = mvr.render(views=1, size=(64, 48), focal_length_mm=50)
    assert r.color.shape == (1, 48, 64, 4)
    with pytest.raises(ValueError, match="--focal-length-mm excludes --fov"):
        mvr.render(views=1, size=(64, 48), focal_length_mm=50, fov=30)


def test_background_colour():
    r = mvr.render(views=1, size=(64, 48), background=(0.2, 0.4, 0.6), azimuth=0, distance=500)
    assert tuple(r.color[0, 0, 0, :3]) == (51, 102, 153)


def test_bad_camera_keywords_raise_value_error_naming_the_option():
    with pytest.raises(ValueError, match=r"--camera-position 1,2: expected X,Y,Z"):
        mvr.render(views=1, size=(64, 48), camera_position=(1, 2))
    with pytest.raises(ValueError, match="the camera is given twice"):
        mvr.render(views=1, size=(64, 48), azimuth=10, camera_position=(1, 2, 3))
    with pytest.raises(ValueError, match="expected numbers"):
        mvr.render(views=1, size=(64, 48), up=("a", 1, 0))


def test_distance_of_a_plane_is_its_distance_and_the_views_carry_the_cameras(tmp_path):
    # A plane z = 0 seen from (0, 0, d): every drawn pixel is d away along the axis.
    d = 7.5
    obj = tmp_path / "plane.obj"
    obj.write_text("v -20 -20 0\nv 20 -20 0\nv 20 20 0\nv -20 20 0\nf 1 2 3 4\n")
    r = mvr.render([obj], views=2, size=(64, 48), camera_position=(0, 0, d), look_at=(0, 0, 0))
    assert r.distance.shape == (2, 48, 64) and r.distance.dtype == np.float32
    np.testing.assert_allclose(r.distance, d, rtol=1e-4)
    away = mvr.render([obj], views=1, size=(64, 48), camera_position=(30, 0, 1), look_at=(0, 0, 1))
    assert np.isinf(away.distance).any()  # nothing drawn there: inf
    # The intrinsics agree with the projection matrix (the OpenCV pinhole of the same camera).
    v = r.views[1]
    k, p = v.intrinsics, v.projection
    assert k["fx"] == pytest.approx(0.5 * 64 * p[0, 0])
    assert k["cx"] == pytest.approx(0.5 * 64 * (1 - p[0, 2]) - 0.5)
    np.testing.assert_allclose(v.world_from_camera @ v.view_matrix, np.eye(4), atol=1e-5)
    np.testing.assert_allclose(v.world_from_camera[:3, 3], r.views[1].world_from_camera[:3, 3])
    assert v.near > 0 and v.far > v.near


def test_a_quilt_layout_without_a_quilt_is_refused():
    with pytest.raises(ValueError, match="--quilt lays out a quilt, and no quilt is written"):
        mvr.render(views=2, size=(32, 24), quilt=(2, 1))
    r = mvr.render(views=2, size=(32, 24), quilt=(2, 1), format="quilt")
    assert r.composites["quilt"].shape[:2] == (24, 64)


def test_png_compression_changes_the_bytes_not_the_pixels(tmp_path):
    sizes = {}
    for mode in ("fast", "default", "small"):
        r = mvr.render(views=1, size=(160, 120), output=str(tmp_path / mode), png_compression=mode)
        sizes[mode] = (tmp_path / mode / "view-0.png").stat().st_size
        assert r.written == [str(tmp_path / mode / "view-0.png")]
    assert sizes["small"] <= sizes["default"] <= sizes["fast"], sizes
    with pytest.raises(ValueError, match="--png-compression tiny: expected fast, default or small"):
        mvr.render(views=1, size=(16, 12), png_compression="tiny")


def test_write_chooses_the_files_as_the_cli(tmp_path, cli):
    r = mvr.render(size=(32, 24), format="sbs", write=["composites"], output=str(tmp_path / "py"))
    assert sorted(p.rsplit("/", 1)[1] for p in r.written) == ["anaglyph.png", "sbs.png"]
    assert r.color.shape[0] == 2  # the images come back whatever is written
    cli("render", "--size", "32x24", "--format", "sbs", "--write", "composites", "-q",
        "-o", tmp_path / "cli")
    assert sorted(os.listdir(tmp_path / "cli")) == sorted(os.listdir(tmp_path / "py"))
    r = mvr.render(size=(32, 24), write="views,depth", output=str(tmp_path / "vd"))
    assert sorted(os.listdir(tmp_path / "vd")) == ["depth-0.png", "depth-1.png", "view-0.png",
                                                   "view-1.png"]
    with pytest.raises(ValueError, match="--write nope: unknown 'nope'"):
        mvr.render(size=(16, 12), write="nope")


def test_a_transparent_background_is_alpha_zero_where_nothing_is_drawn(model):
    t = mvr.render([model], size=(64, 48), background="transparent")
    o = mvr.render([model], size=(64, 48))
    np.testing.assert_array_equal(t.color[..., :3], o.color[..., :3])
    alpha = t.color[..., 3]
    assert set(np.unique(alpha)) == {0, 255}
    assert alpha[0, 0, 0] == 0 and alpha[0, 24, 32] == 255
    with pytest.raises(ValueError, match="--background transparent: not with --letterbox"):
        mvr.render(size=(16, 12), background="transparent", letterbox=5)


def test_an_ignored_keyword_is_a_warning_in_the_notes():
    r = mvr.render(size=(16, 12), shadow_map_size=512)
    assert "warning: --shadow-map-size is ignored without --shadows" in r.rig["notes"]
    assert not any("is ignored" in n for n in mvr.render(size=(16, 12), shadows=True,
                                                       shadow_map_size=512).rig["notes"])


def test_depth_format_exr_writes_distances_beside_the_views(tmp_path):
    r = mvr.render(views=1, size=(32, 24), depth=True, depth_format="exr", output=str(tmp_path))
    assert sorted(os.listdir(tmp_path)) == ["depth-0.exr", "view-0.png"]
    assert (tmp_path / "depth-0.exr").read_bytes()[:4] == b"\x76\x2f\x31\x01"  # OpenEXR's magic
    with pytest.raises(ValueError, match="--depth-format tiff: expected png16 or exr"):
        mvr.render(views=1, size=(16, 12), depth=True, depth_format="tiff")
