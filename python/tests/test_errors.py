"""Bad input of every kind raises a Python exception with mvr's message, never a crash."""
import math
import re

import numpy as np
import pytest

import mvr

USAGE = [
    (dict(views=0), "view count 0 is out of range"),
    (dict(views=-3), "out of range"),
    (dict(views=129), "out of range"),
    (dict(size=(-1, 5)), "--size '-1x5' is out of range"),
    (dict(size=(0, 0)), "out of range"),
    (dict(size="abc"), "is not of the form WxH"),
    (dict(view_grid=(0, 3)), "out of range"),
    (dict(fov=math.nan), "--fov nan is out of range"),
    (dict(fov=math.inf), "out of range"),
    (dict(fov=-1.0), "out of range"),
    (dict(interaxial=math.nan), "--interaxial nan is out of range"),
    (dict(convergence=0.0), "--convergence 0 is out of range"),
    (dict(separation=-0.5), "out of range"),
    (dict(rig="sideways"), "sideways"),
    (dict(shading="toon"), "toon"),
    (dict(tonemap="filmic"), "--tonemap filmic: not a tone mapping"),
    (dict(specular="eye"), "--specular eye: not a shading eye (expected center or per-view)"),
    (dict(specular="per-view", shading="flat"), "--specular per-view needs --shading pixel"),
    (dict(backend="nope"), "unknown backend 'nope'"),
    (dict(method="nope"), "unknown method 'nope'"),
    (dict(grid=3), "--grid 3 needs a model file"),
    (dict(views=2, view_grid=(2, 2)), "excludes"),
    (dict(format="nope"), "nope"),
    (dict(jpeg_quality=500), "--jpeg-quality: 500 is out of range (must be 1..100)"),
    (dict(views=3, format="sbs"), "sbs"),
]


@pytest.mark.parametrize("kwargs,message", USAGE)
def test_bad_parameters_are_value_errors(kwargs, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        mvr.render(size=kwargs.pop("size", (16, 12)), **kwargs)


WRONG_TYPES = [dict(views="two"), dict(views=2.5), dict(views=[2]), dict(views=None, size=3.0),
               dict(cull=1), dict(cull="yes"), dict(fov="wide"), dict(fov=1j), dict(size={}),
               dict(size=(1.5, 2)), dict(bogus=1), dict(help=True), dict(format=[1])]


@pytest.mark.parametrize("kwargs", WRONG_TYPES)
def test_wrong_types_and_unknown_keywords(kwargs):
    with pytest.raises(mvr.ParameterError) as e:
        mvr.render(**kwargs)
    assert isinstance(e.value, TypeError) and isinstance(e.value, ValueError)


def test_files(tmp_path):
    with pytest.raises(FileNotFoundError, match="file not found"):
        mvr.render([tmp_path / "missing.obj"])
    with pytest.raises(FileNotFoundError):
        mvr.load_mesh(str(tmp_path / "missing.ply"))
    junk = tmp_path / "junk.obj"
    junk.write_bytes(b"\x00\x01garbage")
    with pytest.raises(OSError):
        mvr.render([junk], size=(16, 12))
    with pytest.raises(mvr.ParameterError):
        mvr.render([42])
    with pytest.raises(ValueError):
        mvr.render([""])
    with pytest.raises(OSError):
        mvr.write_png(tmp_path / "no" / "such" / "dir.png", np.zeros((2, 2, 4), np.uint8))
    with pytest.raises(FileNotFoundError):
        mvr.compose("sbs", [tmp_path / "a.png", tmp_path / "b.png"])


def test_empty_lists_mean_the_default():
    assert mvr.render([], size=(16, 12)).color.shape == (2, 12, 16, 4)


def test_compose_bad_input():
    with pytest.raises(ValueError, match="0 views given"):
        mvr.compose("sbs", [])
    with pytest.raises(ValueError, match="unknown output format"):
        mvr.compose("nope", np.zeros((2, 4, 4, 4), np.uint8))
    with pytest.raises(mvr.ParameterError):
        mvr.compose("sbs", np.zeros((2, 4, 4, 4), np.float32))
    with pytest.raises(mvr.ParameterError):
        mvr.compose(3, [])
    with pytest.raises(mvr.ParameterError):
        mvr.compose("sbs", 5)
    with pytest.raises(ValueError):
        mvr.compose("sbs", np.zeros((2, 0, 4, 4), np.uint8))
    with pytest.raises(ValueError):
        mvr.compose("sbs", np.zeros((2, 4, 4), np.uint8))
    with pytest.raises(ValueError, match="differ in size"):
        mvr.compose("sbs", [np.zeros((4, 4, 4), np.uint8), np.zeros((4, 5, 4), np.uint8)])
    with pytest.raises(ValueError):
        mvr.compose("sbs-half", np.zeros((2, 4, 5, 4), np.uint8))
    with pytest.raises(ValueError):
        mvr.compose("quilt", np.zeros((2, 4, 4, 4), np.uint8), quilt=(0, 1))
    with pytest.raises(mvr.ParameterError):
        mvr.compose("sbs", np.zeros((2, 4, 4, 4), np.uint8), bogus=1)
    with pytest.raises(ValueError):
        mvr.compose("lenticular", np.zeros((2, 4, 4, 4), np.uint8), lenticular_slope=0.0)


def test_write_png_bad_input(tmp_path):
    for bad in [np.zeros((0, 3, 4), np.uint8), np.zeros((3, 3, 5), np.uint8), np.zeros(3, np.uint8)]:
        with pytest.raises(ValueError):
            mvr.write_png(tmp_path / "x.png", bad)
    with pytest.raises(mvr.ParameterError):
        mvr.write_png(tmp_path / "x.png", [[1, 2]])
    with pytest.raises(mvr.ParameterError):
        mvr.write_png(tmp_path / "x.png", np.zeros((3, 3, 4), np.int64))
    with pytest.raises(mvr.ParameterError):
        mvr.write_png(5, np.zeros((3, 3, 4), np.uint8))


def test_values_never_read_as_options(tmp_path):
    with pytest.raises(ValueError):
        mvr.render(rig="--cull", size=(16, 12))
    with pytest.raises(FileNotFoundError, match="lenticular_calibration"):
        mvr.render(size=(16, 12), lenticular_calibration=tmp_path / "visual.json")
    with pytest.raises(FileNotFoundError):
        mvr.compose("lenticular", np.zeros((2, 4, 4, 4), np.uint8),
                    lenticular_calibration=str(tmp_path / "none.json"))


def test_too_much_memory_is_refused_not_allocated():
    with pytest.raises(RuntimeError):
        mvr.render(views=64, size=(16384, 16384))


def test_unwritable_output(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    with pytest.raises(OSError, match="cannot create output directory"):
        mvr.render(size=(16, 12), output=blocker / "out")
    with pytest.raises(OSError):
        mvr.compose("sbs", np.zeros((2, 4, 4, 4), np.uint8), output=blocker / "x.png")


def test_a_failed_render_leaves_no_file(tmp_path):
    """Issue 44: the images and the report are one set; a report that cannot be written is
    refused before anything is rendered, and the output folder is not even made."""
    (tmp_path / "report.json").mkdir()
    with pytest.raises(OSError, match="report.json: not a regular file"):
        mvr.render(views=2, size=(32, 24), output=str(tmp_path / "out"),
                   report_json=str(tmp_path / "report.json"))
    assert not (tmp_path / "out").exists()
    r = mvr.render(views=2, size=(32, 24), output=str(tmp_path / "out2"),
                   report_json=str(tmp_path / "sub" / "report.json"))
    assert (tmp_path / "sub" / "report.json").is_file()
    assert sorted(p.name for p in (tmp_path / "out2").iterdir()) == [
        "anaglyph.png", "view-0.png", "view-1.png"]
    assert not [p for p in tmp_path.rglob("*") if "mvr-part" in p.name]
