"""mvr.from_rgbd: a display's views from an RGB-D picture, as `mvr compose --from-rgbd` makes
them (docs/displays.md, "RGB-D in, quilt out")."""
import math
import os
import subprocess

import numpy as np
import pytest

import mvr
from conftest import read_png

W, H = 420, 560  # the Portrait's view, 48 views over a 40 degree cone, picture aspect 0.75


def bar_pair(tmp_path, grey):
    colour = np.zeros((H, W, 4), np.uint8)
    colour[..., 3] = 255
    colour[:, 200:220, :3] = 255
    depth = np.full((H, W, 4), grey, np.uint8)
    depth[..., 3] = 255
    mvr.write_png(tmp_path / "colour.png", colour)
    mvr.write_png(tmp_path / "depth.png", depth)
    return [tmp_path / "colour.png", tmp_path / "depth.png"]


def centre(view):
    row = view[H // 2, :, 0].astype(float)
    return float((row * (np.arange(W) + 0.5)).sum() / row.sum())


def expected(t, a, spread=1.0):
    # View t looks from C tan(theta_t) beside the centre; the focal plane's window is
    # 2 C aspect tan(fovY / 2) wide (mvr's default camera: 45 degrees).
    theta = math.radians(-20.0 + 40.0 * t / 47)
    shear = math.tan(theta) * spread / (0.75 * math.tan(math.radians(22.5)))
    return 210.0 + shear * a * W / 2


def test_a_foreign_depth_map_is_disparity(tmp_path):
    files = bar_pair(tmp_path, 255)
    views = mvr.from_rgbd(files, "portrait")
    assert views.shape == (48, H, W, 4) and views.dtype == np.uint8
    for t in (0, 11, 47):
        assert centre(views[t]) == pytest.approx(expected(t, -0.5), abs=0.1)
    half = mvr.from_rgbd([str(f) for f in files], "portrait", depthiness=0.5, focus=0.05)
    for t in (0, 47):
        assert centre(half[t]) == pytest.approx(expected(t, -0.45, 0.5), abs=0.1)


def test_the_views_are_the_tools(tmp_path):
    files = bar_pair(tmp_path, 100)
    views = mvr.from_rgbd(files, "portrait")
    quilt = mvr.compose("quilt", views, quilt=(8, 6))
    cli = os.environ.get("MVR_CLI")
    if not cli:
        pytest.skip("MVR_CLI not set")
    subprocess.run([cli, "compose", str(files[0]), str(files[1]), "--from-rgbd", "--display",
                    "portrait", "-q", "-o", str(tmp_path / "out")], check=True)
    written = read_png(tmp_path / "out" / "quilt_qs8x6a0.75.png")
    assert np.array_equal(quilt, written)


def test_bad_input(tmp_path):
    files = bar_pair(tmp_path, 10)
    with pytest.raises(ValueError, match=r"--display 3dtv: --from-rgbd needs a light-field display"):
        mvr.from_rgbd(files, "3dtv")
    with pytest.raises(ValueError, match=r"focus 0.2 is out of range \(expected -0.05..0.05\)"):
        mvr.from_rgbd(files, "portrait", focus=0.2)
    with pytest.raises(ValueError, match=r"3 files given"):
        mvr.from_rgbd(files + files[:1], "portrait")
    with pytest.raises(FileNotFoundError):
        mvr.from_rgbd([tmp_path / "nope.png"], "portrait")
