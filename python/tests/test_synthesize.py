"""mvr.render(synthesize=K): the CLI's --synthesize (mvr/core/synthesize.h) pixel for pixel, the
exact views the plain render's, the warped ones close to theirs, and the refusals."""
import re

import numpy as np
import pytest

import mvr
from conftest import read_png

COMMON = dict(views=9, size=(160, 120))


def test_synthesize_equals_cli(cli, tmp_path):
    cli("render", "--views", "9", "--size", "160x120", "--synthesize", "4", "-o", tmp_path)
    r = mvr.render(**COMMON, synthesize=4)
    assert r.color.shape == (9, 120, 160, 4)
    for v in range(9):
        np.testing.assert_array_equal(r.color[v], read_png(tmp_path / f"view-{v}.png"))


def test_exact_views_are_the_plain_render_and_warped_ones_close():
    plain = mvr.render(**COMMON).color
    warped = mvr.render(**COMMON, synthesize=4).color
    for v in (0, 4, 8):
        np.testing.assert_array_equal(warped[v], plain[v])
    for v in (1, 2, 3, 5, 6, 7):
        diff = warped[v, ..., :3].astype(np.float64) - plain[v, ..., :3]
        psnr = 10 * np.log10(255.0 ** 2 / np.mean(diff ** 2))
        assert psnr > 25.0, (v, psnr)
    assert np.array_equal(mvr.render(**COMMON, synthesize=1).color, plain)


@pytest.mark.parametrize("extra,message", [
    (dict(synthesize=0), "--synthesize 0 is out of range (expected 1..64; 1: every view exact)"),
    (dict(synthesize=65), "--synthesize 65 is out of range (expected 1..64; 1: every view exact)"),
    (dict(synthesize=4, views=2),
     "--synthesize 4: needs rows of at least 3 views (the rig has 2 views in 1 row)"),
    (dict(synthesize=4, rig="toein"), "--synthesize 4: needs an off-axis rig"),
])
def test_refusals(extra, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        mvr.render(**{**COMMON, **extra})


def test_not_an_integer():
    with pytest.raises(mvr.ParameterError):
        mvr.render(**COMMON, synthesize="four")
