"""mvr.render() and mvr.compose() give the CLI's images pixel for pixel."""
import re

import numpy as np
import pytest

import mvr
from conftest import read_png

CASES = [
    ({}, []),
    ({"views": 3, "rig": "toein", "shading": "pixel", "cull": True},
     ["--views", "3", "--rig", "toein", "--shading", "pixel", "--cull"]),
    ({"view_grid": (3, 2), "interaxial": 0.3, "convergence": 5.5, "fov": 40.0},
     ["--view-grid", "3x2", "--interaxial", "0.3", "--convergence", "5.5", "--fov", "40"]),
    ({"views": 2, "rig": "parallel", "separation": 0.05, "shading": "flat", "method": "multipass"},
     ["--views", "2", "--rig", "parallel", "--separation", "0.05", "--shading", "flat",
      "--method", "multipass"]),
    ({"tonemap": "aces", "shading": "pixel"}, ["--tonemap", "aces", "--shading", "pixel"]),
    ({"views": 5, "interaxial": 0.5, "specular": "per-view"},
     ["--views", "5", "--interaxial", "0.5", "--specular", "per-view"]),
    ({"sky": "gradient", "floating_window": True, "letterbox": 8, "label": ["HI@0.5,0.3,3"],
      "label_anchor": "A@0,0.5,0"},
     ["--sky", "gradient", "--floating-window", "--letterbox", "8", "--label", "HI@0.5,0.3,3",
      "--label-anchor", "A@0,0.5,0"]),
]


def _compare(result, outdir, count):
    for v in range(count):
        np.testing.assert_array_equal(result.color[v], read_png(outdir / f"view-{v}.png"))


@pytest.mark.parametrize("kwargs,args", CASES)
def test_default_scene_equals_cli(cli, tmp_path, kwargs, args):
    stdout = cli("render", "--size", "96x64", "--depth", "-o", tmp_path, *args)
    r = mvr.render(size=(96, 64), **kwargs)
    n = r.color.shape[0]
    assert r.color.shape == (n, 64, 96, 4) and r.color.dtype == np.uint8
    assert r.depth.shape == (n, 64, 96) and r.depth.dtype == np.float32
    _compare(r, tmp_path, n)
    for v in range(n):  # the depth as `--depth` writes it
        mvr.write_png(tmp_path / f"py-depth-{v}.png", r.depth[v])
        assert (tmp_path / f"py-depth-{v}.png").read_bytes() == (tmp_path / f"depth-{v}.png").read_bytes()
    assert f"{r.backend}:{r.method}" in stdout
    rig = re.search(r"rig: (\w+) (\d+)x(\d+), interaxial (\S+), convergence (\S+), separation (\S+)%",
                    stdout)
    assert rig.group(1) == r.rig["kind"]
    assert (int(rig.group(2)), int(rig.group(3))) == (r.rig["columns"], r.rig["rows"])
    assert f"{r.rig['interaxial']:.4g}" == rig.group(4)
    assert f"{r.rig['convergence']:.4g}" == rig.group(5)
    assert f"{100 * r.rig['separation']:.2f}" == rig.group(6)
    if r.rig["columns"] > 1:
        assert r.comfort["text"] in stdout
        assert isinstance(r.comfort["comfortable"], bool)
    if n == 2:  # the anaglyph every stereo render gets
        np.testing.assert_array_equal(mvr.compose("anaglyph-dubois", r.color),
                                      read_png(tmp_path / "anaglyph.png"))


def test_model_grid_wireframe_equals_cli(cli, tmp_path, model):
    cli("render", model, "--grid", "3", "--wireframe", "--size", "80x60", "--views", "4",
        "--format", "quilt", "--format", "mpo", "--quilt", "2x2", "-o", tmp_path)
    r = mvr.render([model], grid=3, wireframe=True, size=(80, 60), views=4,
                   format=["quilt", "mpo"], quilt=(2, 2))
    assert r.triangles == 18 and str(model) in r.scene
    _compare(r, tmp_path, 4)
    np.testing.assert_array_equal(r.composites["quilt"], read_png(tmp_path / "quilt_qs2x2a1.3333.png"))
    assert r.composites["mpo"] == (tmp_path / "mpo.mpo").read_bytes()


def test_gl_backend_equals_cli(cli, tmp_path):
    info = {b["name"]: b for b in mvr.info()["backends"]}
    if not info.get("gl", {}).get("available"):
        pytest.skip("no gl backend here")
    cli("render", "--backend", "gl", "--method", "multipass", "--size", "64x48", "-o", tmp_path)
    r = mvr.render(backend="gl", method="multipass", size=(64, 48))
    assert r.method == "multipass"
    _compare(r, tmp_path, 2)


def test_compose_equals_cli(cli, tmp_path):
    r = mvr.render(views=2, size=(64, 48))
    files = []
    for v in range(2):
        files.append(tmp_path / f"v{v}.png")
        mvr.write_png(files[-1], r.color[v])
    for fmt, extra, kw in [("sbs", [], {}), ("tb-half", ["--swap-eyes"], {"swap_eyes": True}),
                           ("anaglyph-gray", [], {})]:
        cli("compose", *files, "-f", fmt, "-q", "-o", tmp_path / f"{fmt}.png", *extra)
        expected = read_png(tmp_path / f"{fmt}.png")
        np.testing.assert_array_equal(mvr.compose(fmt, r.color, **kw), expected)
        np.testing.assert_array_equal(mvr.compose(fmt, files, **kw), expected)
        np.testing.assert_array_equal(mvr.compose(fmt, [r.color[0][..., :3], r.color[1]], **kw),
                                      expected)
    cli("compose", *files, "-q", "-o", tmp_path / "pair.jps", "--jpeg-quality", "80")
    assert mvr.compose("jps", r.color, jpeg_quality=80) == (tmp_path / "pair.jps").read_bytes()
    cli("compose", *files, "-q", "-o", tmp_path / "pair.mpo", "--baseline", "0.065")
    assert mvr.compose("mpo", files, baseline=0.065) == (tmp_path / "pair.mpo").read_bytes()


def test_smoke_shape():
    r = mvr.render(views=2, size=(320, 240))
    assert r.color.shape == (2, 240, 320, 4)
    assert len(r) == 2 and "2 views of 320x240" in repr(r)


def test_stereo_surfaces_errors():
    with pytest.raises(FileNotFoundError, match="nosuch.png"):
        mvr.render(size=(32, 24), sky="nosuch.png")
    with pytest.raises(ValueError, match="--label 'bad'"):
        mvr.render(size=(32, 24), label="bad")


def test_load_mesh_and_info(model):
    m = mvr.load_mesh(model)
    assert m["positions"].shape == (5, 3) and m["positions"].dtype == np.float32
    assert m["indices"].shape == (6, 3) and m["indices"].dtype == np.uint32
    assert m["triangles"] == 6 and m["indices"].max() < 5
    i = mvr.info()
    assert i["limits"]["max_views"] >= 64
    soft = next(b for b in i["backends"] if b["name"] == "soft")
    assert soft["available"] and soft["default_method"] in [m["name"] for m in soft["methods"]]
    assert all(isinstance(m["supported"], bool) for m in soft["methods"])
    assert "quilt" in [f["name"] for f in i["formats"]]


def test_write_png_round_trip(tmp_path):
    a = np.zeros((5, 7, 4), np.uint8)
    a[..., 0] = np.arange(7)
    a[..., 3] = 255
    mvr.write_png(tmp_path / "a.png", a)
    np.testing.assert_array_equal(read_png(tmp_path / "a.png"), a)
    mvr.write_png(tmp_path / "b.png", a[..., :3])
    np.testing.assert_array_equal(read_png(tmp_path / "b.png"), a)
    mvr.write_png(tmp_path / "c.png", a[:, ::2])  # not contiguous
    np.testing.assert_array_equal(read_png(tmp_path / "c.png"), a[:, ::2])


def test_output_writes_the_cli_files(cli, tmp_path):
    cli("render", "--size", "48x32", "--depth", "--format", "sbs", "--format", "jps", "-q",
        "-o", tmp_path / "cli")
    r = mvr.render(size=(48, 32), depth=True, format=["sbs", "jps"], output=tmp_path / "py")
    names = sorted(p.name for p in (tmp_path / "cli").iterdir())
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == names
    assert sorted(__import__("os").path.basename(w) for w in r.written) == names
    for name in names:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    files = [tmp_path / "cli" / "view-0.png", tmp_path / "cli" / "view-1.png"]
    cli("compose", *files, "-f", "tb", "-q", "-o", tmp_path / "cli-compose")
    mvr.compose("tb", files, output=tmp_path / "py-compose", quiet=True)
    assert (tmp_path / "py-compose" / "tb.png").read_bytes() == (tmp_path / "cli-compose" / "tb.png").read_bytes()
    mvr.compose("mpo", files, output=tmp_path / "sub" / "pair.mpo")
    cli("compose", *files, "-q", "-o", tmp_path / "pair.mpo")
    assert (tmp_path / "sub" / "pair.mpo").read_bytes() == (tmp_path / "pair.mpo").read_bytes()


def test_vk_backend_equals_cli(cli, tmp_path):
    info = {b["name"]: b for b in mvr.info()["backends"]}
    if not info.get("vk", {}).get("available"):
        pytest.skip("no vk backend here")
    cli("render", "--backend", "vk", "--method", "multiview", "--views", "8", "--size", "64x48",
        "-o", tmp_path)
    r = mvr.render(backend="vk", method="multiview", views=8, size=(64, 48))
    assert r.method == "multiview"
    _compare(r, tmp_path, 8)
