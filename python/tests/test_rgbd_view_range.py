"""Issue 42: view_range=(A, B) renders views A..B of the whole rig; format="rgbd" gives the
centre view's colour and depth side by side, as `mvr render` does."""
import json
import re

import numpy as np
import pytest

import mvr
from conftest import read_png


def test_view_range_is_the_whole_renders_views(cli, tmp_path):
    whole = mvr.render(views=6, size=(64, 48))
    part = mvr.render(views=6, size=(64, 48), view_range=(2, 4), output=tmp_path / "py")
    assert part.color.shape == (3, 48, 64, 4)
    np.testing.assert_array_equal(part.color, whole.color[2:5])
    np.testing.assert_array_equal(part.depth, whole.depth[2:5])
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == [
        "view-2.png", "view-3.png", "view-4.png"]
    # the same files as `mvr render --view-range 2:4`, and a string works too
    cli("render", "--views", "6", "--size", "64x48", "--view-range", "2:4", "-o", tmp_path / "cli")
    for v in (2, 3, 4):
        assert (tmp_path / "cli" / f"view-{v}.png").read_bytes() == \
            (tmp_path / "py" / f"view-{v}.png").read_bytes()
    again = mvr.render(views=6, size=(64, 48), view_range="2:4")
    np.testing.assert_array_equal(again.color, part.color)


@pytest.mark.parametrize("view_range,message", [
    ((5, 2), "--view-range '5:2' is out of range (expected 0 <= A <= B <= 5"),
    ((0, 99), "--view-range '0:99' is out of range"),
    ("a:b", "--view-range 'a:b' is not of the form A:B"),
])
def test_bad_view_ranges(view_range, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        mvr.render(views=6, size=(32, 24), view_range=view_range)


def test_view_range_refuses_composites():
    with pytest.raises(ValueError, match=re.escape("--view-range 0:1: not with --format quilt")):
        mvr.render(views=6, size=(32, 24), view_range=(0, 1), format="quilt")


def test_rgbd_equals_cli(cli, tmp_path):
    cli("render", "--views", "3", "--size", "64x48", "--format", "rgbd", "--depthiness", "0.5",
        "--rgbd-depth-position", "bottom", "-o", tmp_path / "cli")
    r = mvr.render(views=3, size=(64, 48), format="rgbd", depthiness=0.5,
                   rgbd_depth_position="bottom", output=tmp_path / "py")
    rgbd = r.composites["rgbd"]
    assert rgbd.shape == (96, 64, 4)
    np.testing.assert_array_equal(rgbd, read_png(tmp_path / "cli" / "rgbd.png"))
    np.testing.assert_array_equal(rgbd[:48], r.color[1])  # the centre view on top
    side = json.loads((tmp_path / "py" / "rgbd.json").read_text())
    assert side["settings"]["depth_loc"] == 1 and side["settings"]["depthiness"] == 0.5
    assert side == json.loads((tmp_path / "cli" / "rgbd.json").read_text())
    # white = near: the depth decodes to the distances the render gives (within half a step)
    near, far = side["mvr"]["near"], side["mvr"]["far"]
    g = rgbd[48:, :, 0].astype(np.float64)
    dist = r.distance[1]
    drawn = np.isfinite(dist)
    assert drawn.any()
    decoded = far - g / 255.0 * (far - near)
    assert np.abs(decoded[drawn] - dist[drawn]).max() <= (far - near) / 510 + 1e-3
    assert (g[~drawn] == 0).all()


def test_rgbd_needs_a_centre_view():
    with pytest.raises(ValueError, match=re.escape(
            "--format rgbd: the RGB-D image is the rig's centre view, and a row of 2 views has none")):
        mvr.render(views=2, size=(32, 24), format="rgbd")


def test_depthiness_and_focus_on_the_view_cone():
    """Issue 42 item 3: depthiness= scales the view cone's spread (0: identical views), focus=
    moves its focal plane by F of the scene's bounding-box diagonal (session/cone_depth.h)."""
    kw = dict(views=5, view_cone=30, size=(48, 36), aa=1, angular_aa="off")
    flat = mvr.render(depthiness=0, **kw)
    for v in range(5):
        np.testing.assert_array_equal(flat.color[v], flat.color[2])
    whole = mvr.render(**kw)
    assert not np.array_equal(whole.color[0], whole.color[4])
    half = mvr.render(depthiness=0.5, **kw)
    for v in range(5):
        ex = lambda r: r.views[v].world_from_camera[0, 3]
        assert abs(ex(half) - 0.5 * ex(whole)) < 1e-4
    with pytest.raises(ValueError, match="--depthiness 0: the RGB-D sidecar takes"):
        mvr.render(depthiness=0, format="rgbd", views=3, view_cone=30, size=(48, 36))
