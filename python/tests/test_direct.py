"""mvr.render(direct=True): `mvr render --direct` (mvr/session/direct.h) — the lenticular panel
composed from the views' rows, the same pixels as composing the rendered views (the CLI's file
and mvr.render's own composite), no views returned, and the refusals."""
import re

import numpy as np
import pytest

import mvr
from conftest import read_png

CAL = ('{"pitch": {"value": 52.59}, "slope": {"value": -7.08}, "center": {"value": 0.82}, '
       '"DPI": {"value": 324.0}, "screenW": {"value": 240}, "screenH": {"value": 320}, '
       '"invView": {"value": 1}, "flipSubp": {"value": 1}}')


@pytest.fixture
def cal(tmp_path):
    path = tmp_path / "visual.json"
    path.write_text(CAL)
    return path


def test_direct_equals_the_composed_views_and_the_cli(cli, tmp_path, cal):
    common = dict(views=8, size=(60, 80), format="lenticular", lenticular_calibration=cal, aa=2)
    composed = mvr.render(**common).composites["lenticular"]
    r = mvr.render(**common, direct=True, output=tmp_path / "py")  # no view written by default
    assert r.color is None and r.depth is None
    panel = r.composites["lenticular"]
    assert panel.shape == (320, 240, 4)
    np.testing.assert_array_equal(panel, composed)
    assert [p.rsplit("/", 1)[-1] for p in r.written] == ["lenticular.png"]
    np.testing.assert_array_equal(read_png(tmp_path / "py" / "lenticular.png"), panel)
    cli("render", "--views", "8", "--size", "60x80", "--format", "lenticular",
        "--lenticular-calibration", cal, "--aa", "2", "--direct", "-o", tmp_path / "cli")
    np.testing.assert_array_equal(read_png(tmp_path / "cli" / "lenticular.png"), panel)


@pytest.mark.parametrize("extra,message", [
    (dict(), "direct: renders the lenticular panel image; give --format lenticular"),
    (dict(format=["lenticular", "quilt"]),
     "direct: writes the lenticular image alone, and --format also asks for quilt"),
    (dict(format="lenticular", sky="gradient"), "direct: --sky is drawn over whole views"),
])
def test_refusals(cal, extra, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        mvr.render(views=4, size=(30, 40), lenticular_calibration=cal, direct=True, **extra)


def test_multipass_and_sequences_are_refused(cal):
    with pytest.raises(RuntimeError, match=re.escape("direct: soft:multipass renders whole views")):
        mvr.render(views=4, size=(30, 40), lenticular_calibration=cal, format="lenticular",
                   method="multipass", direct=True)
    with pytest.raises(ValueError, match=re.escape("direct: renders a still")):
        mvr.render_sequence(views=4, size=(30, 40), frames=2, direct=True)
