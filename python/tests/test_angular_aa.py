"""mvr.render(angular_aa=): the CLI's --angular-aa (mvr/core/angular_aa.h) pixel for pixel, what
auto means, the refusals, and the inter-view flicker of far content before and after."""
import re

import numpy as np
import pytest

import mvr
from conftest import read_png


@pytest.fixture(scope="module")
def bars(tmp_path_factory):
    """Thin vertical bars at z = -5 and a small square at z = 5 (symmetric: a plain model is
    centred on its bounds). From (0, 0, 10) with convergence 5: the square on the focal plane,
    the bars at 3 x the convergence distance."""
    lines, v = [], 0
    def quad(x0, x1, y0, y1, z):
        nonlocal v
        lines.append(f"v {x0} {y0} {z}\nv {x1} {y0} {z}\nv {x1} {y1} {z}\nv {x0} {y1} {z}\n")
        lines.append(f"f {v + 1} {v + 2} {v + 3}\nf {v + 1} {v + 3} {v + 4}\n")
        v += 4
    for i in range(-40, 41):
        quad(0.2 * i - 0.05, 0.2 * i + 0.05, -3, 3, -5)
    quad(-0.3, 0.3, -0.3, 0.3, 5)
    path = tmp_path_factory.mktemp("bars") / "bars.obj"
    path.write_text("".join(lines))
    return path


def common(bars):
    return dict(models=[str(bars)], camera_position=(0, 0, 10), look_at=(0, 0, 0),
                convergence=5, views=8, size=(160, 120))


def flicker(color):
    """Mean absolute RGB difference between adjacent views (an off-axis rig's focal-plane shift
    is 0: nothing to remove first)."""
    c = color[..., :3].astype(np.int32)
    return float(np.abs(c[1:] - c[:-1]).mean())


def test_angular_aa_equals_cli(cli, tmp_path, bars):
    cli("render", bars, "--camera-position", "0,0,10", "--look-at", "0,0,0", "--convergence",
        "5", "--views", "8", "--size", "160x120", "--angular-aa", "1.5", "-o", tmp_path)
    r = mvr.render(**common(bars), angular_aa=1.5)
    for v in range(8):
        np.testing.assert_array_equal(r.color[v], read_png(tmp_path / f"view-{v}.png"))


def test_auto_off_and_a_scale(bars):
    off = mvr.render(**common(bars), angular_aa="off").color
    assert np.array_equal(mvr.render(**common(bars)).color, off)  # auto: a plain render
    one = mvr.render(**common(bars), angular_aa=1).color
    assert np.array_equal(mvr.render(**common(bars), angular_aa="1").color, one)
    assert not np.array_equal(one, off)
    cone = {**common(bars), "view_cone": 20}
    assert np.array_equal(mvr.render(**cone).color, mvr.render(**cone, angular_aa=1.0).color)
    # The square on the focal plane keeps its pixels (its inner 9 x 9).
    np.testing.assert_array_equal(one[:, 56:65, 76:85], off[:, 56:65, 76:85])


def test_flicker_far_behind_the_focal_plane_is_at_least_halved(bars):
    before = flicker(mvr.render(**common(bars), angular_aa="off").color)
    after = flicker(mvr.render(**common(bars), angular_aa=1).color)
    assert before > 5.0
    assert after <= 0.5 * before, (before, after)


@pytest.mark.parametrize("value,message", [
    ("fuzzy", "--angular-aa fuzzy: expected auto, off or a scale 0 < S <= 100"),
    (0, "--angular-aa 0: expected auto, off or a scale 0 < S <= 100"),
    (-1.5, "--angular-aa -1.5: expected auto, off or a scale 0 < S <= 100"),
])
def test_bad_values(bars, value, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        mvr.render(**common(bars), angular_aa=value)


def test_refusals(bars):
    with pytest.raises(ValueError, match=re.escape("--angular-aa 2: needs more than one view")):
        mvr.render(**{**common(bars), "views": 1}, angular_aa=2)
    with pytest.raises(ValueError, match=re.escape("--angular-aa 1: needs an off-axis rig")):
        mvr.render(**common(bars), rig="toein", angular_aa=1)
    with pytest.raises(mvr.ParameterError):
        mvr.render(**common(bars), angular_aa=True)
