"""display= (the presets of include/mvr/core/displays.h), the comfort report against a screen and
--convergence auto through mvr.render(), checked against the CLI's files and the view-cone
formulas (docs/displays.md)."""
import json
import math
import os

import numpy as np
import pytest

import mvr
from conftest import read_png


def test_portrait_preset_follows_the_view_cone(cli, tmp_path, model):
    cli("render", model, "--display", "portrait", "--write", "views,composites", "-q", "-o", tmp_path)
    r = mvr.render([model], display="portrait", output=tmp_path / "py")
    # A preset writes its quilt alone unless write= names the views (as --write).
    assert sorted(os.listdir(tmp_path / "py")) == ["quilt_qs8x6a0.75.png"]
    assert r.color.shape == (48, 560, 420, 4)
    assert r.rig["views"] == 48 and r.rig["view_cone"] == 40.0
    assert abs(r.rig["aspect"] - 0.75) < 1e-6
    quilt = r.composites["quilt"]
    assert quilt.shape == (3360, 3360, 4)
    np.testing.assert_array_equal(quilt, read_png(tmp_path / "quilt_qs8x6a0.75.png"))
    assert (tmp_path / "py" / "quilt_qs8x6a0.75.png").read_bytes() == \
        (tmp_path / "quilt_qs8x6a0.75.png").read_bytes()
    for v in (0, 23, 47):
        np.testing.assert_array_equal(r.color[v], read_png(tmp_path / f"view-{v}.png"))
    # The camera offsets, computed here: view i at angle -20 + 40 i / 47 degrees seen from the
    # focal plane's centre, shifted sideways by D tan(angle), D = the convergence.
    eyes = np.array(r.rig["eyes"])
    centre = (eyes[23] + eyes[24]) / 2
    d = r.rig["convergence"]
    right = eyes[47] - eyes[0]
    right /= np.linalg.norm(right)
    for i in range(48):
        angle = math.radians(-20.0 + 40.0 * i / 47)
        expected = d * math.tan(angle)
        assert abs(np.dot(eyes[i] - centre, right) - expected) < 1e-4 * d, i
        assert np.linalg.norm(eyes[i] - centre - expected * right) < 1e-4 * d, i


def test_display_errors_and_overrides(model):
    with pytest.raises(ValueError, match="unknown display 'nosuch'.*portrait"):
        mvr.render(display="nosuch")
    r = mvr.render([model], display="portrait", views=3, size=(30, 40), format="quilt")
    assert r.color.shape == (3, 40, 30, 4)


def test_screen_report_and_auto(tmp_path, model):
    r = mvr.render([model], size=(96, 72), convergence="auto", screen_width=30.0,
                   viewing_distance=60.0, report_json=tmp_path / "r.json")
    report = json.loads((tmp_path / "r.json").read_text())
    c = report["rig"]["convergence"]
    assert c == pytest.approx(r.rig["convergence"], rel=1e-5)
    assert report["parallax"]["nearest_distance"] < c < report["parallax"]["farthest_distance"]
    assert any(n.startswith("note: --convergence auto chose") for n in r.rig["notes"])
    s = r.comfort["screen"]
    assert s["desktop"] and s["budget_cm"] == pytest.approx(3.25)
    assert s["min_parallax_cm"] == pytest.approx(report["screen"]["min_parallax_cm"])
    assert report["screen"]["min_parallax_cm"] == pytest.approx(30.0 * report["screen"]["min_parallax"])
    assert isinstance(report["comfortable"], bool)


def test_calibration_view_cone_is_the_default_cone(tmp_path, model):
    # visual.json's viewCone spreads a row of views (as `mvr render --lenticular-calibration`);
    # view_cone= still wins. The eyes sit at D tan(-15 + 30 i / 4) degrees, computed here.
    cal = tmp_path / "visual.json"
    cal.write_text('{"pitch": {"value": 52.59}, "slope": {"value": -7.08}, '
                   '"center": {"value": 0.82}, "DPI": {"value": 324.0}, "viewCone": {"value": 30}}')
    r = mvr.render([model], views=5, size=(32, 24), lenticular_calibration=cal)
    assert r.rig["view_cone"] == 30.0
    assert any("from the calibration's viewCone" in n for n in r.rig["notes"])
    eyes = np.array(r.rig["eyes"])
    d = r.rig["convergence"]
    right = (eyes[4] - eyes[0]) / np.linalg.norm(eyes[4] - eyes[0])
    for i in range(5):
        expected = d * math.tan(math.radians(-15.0 + 30.0 * i / 4))
        assert abs(np.dot(eyes[i] - eyes[2], right) - expected) < 1e-4 * d, i
    r = mvr.render([model], views=5, size=(32, 24), lenticular_calibration=cal, view_cone=20)
    assert r.rig["view_cone"] == 20.0


def test_separation_auto_keeps_the_budget_and_depth_percent(tmp_path, model):
    # Issue 42 item 0: the parallax the eyes meet — at infinity (the separation) and over the
    # scene, s (1 - C / w) computed here — within the budget 6.5 cm / width (half at 60 cm).
    budget = 0.5 * 6.5 / 30.0
    for percent, kw in ((100.0, {}), (40.0, {"depth_percent": 40.0})):
        r = mvr.render([model], size=(96, 72), convergence="auto", separation="auto",
                       screen_width=30.0, viewing_distance=60.0,
                       report_json=tmp_path / "s.json", **kw)
        report = json.loads((tmp_path / "s.json").read_text())
        s, c = report["rig"]["separation"], report["rig"]["convergence"]
        near, far = report["parallax"]["nearest_distance"], report["parallax"]["farthest_distance"]
        worst = max(abs(s * (1 - c / near)), abs(s * (1 - c / far)), s)
        assert worst == pytest.approx(percent / 100.0 * budget, rel=1e-3)
        assert r.comfort["screen"]["infinity_parallax_cm"] == pytest.approx(30.0 * s, rel=1e-4)
        assert r.comfort["screen"]["comfortable"] and report["comfortable"]
    for bad in (0, -5, 101):
        with pytest.raises(ValueError, match=f"--depth-percent {bad} is out of range"):
            mvr.render([model], separation="auto", screen_width=30.0, depth_percent=bad)
    with pytest.raises(ValueError, match="--depth-percent 50 needs --separation auto"):
        mvr.render([model], screen_width=30.0, depth_percent=50)
