"""environment= (--environment MAP): image lighting, the CLI's pixels, and its faults."""
import math
import struct

import numpy as np
import pytest

import mvr
from conftest import read_png


def write_radiance(path, width, height, top, bottom):
    """A flat RGBE file: `top` above the horizon row, `bottom` below (exact RGBE values)."""
    rows = []
    for y in range(height):
        c = top if y < height // 2 else bottom
        v = max(c)
        m, e = math.frexp(v)
        scale = m * 256.0 / v
        texel = struct.pack("4B", *(int(x * scale) for x in c), e + 128)
        rows.append(texel * width)
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n".encode()
    path.write_bytes(header + b"".join(rows))


def test_environment_equals_cli_and_lights_the_scene(cli, tmp_path):
    hdr = tmp_path / "sky.hdr"
    write_radiance(hdr, 64, 32, (0.5, 0.5, 0.5), (0.25, 0.125, 0.0625))
    cli("render", "--size", "96x64", "--environment", hdr, "--sky", "environment",
        "--shading", "pixel", "-o", tmp_path / "cli")
    lit = mvr.render(size=(96, 64), environment=hdr, sky="environment", shading="pixel")
    for v in range(lit.color.shape[0]):
        np.testing.assert_array_equal(lit.color[v], read_png(tmp_path / "cli" / f"view-{v}.png"))
    # The map lights the surfaces: against the same sky over the unlit scene.
    unlit = mvr.render(size=(96, 64), shading="pixel", sky=hdr)
    differ = np.abs(lit.color[0].astype(int) - unlit.color[0].astype(int)).max(axis=2) > 8
    assert differ.mean() > 0.25
    # The sky shows the map: radiance 0.5 above the horizon is 128 in the top corner.
    assert tuple(lit.color[0][0, 0, :3]) == (128, 128, 128)


def test_environment_faults_are_python_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="file not found"):
        mvr.render(size=(32, 32), environment=tmp_path / "nosuch.hdr")
    bad = tmp_path / "bad.hdr"
    bad.write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n\x01\x02")
    with pytest.raises(Exception, match=r"the file ends early"):
        mvr.render(size=(32, 32), environment=bad)
    with pytest.raises(ValueError, match="--sky environment needs --environment MAP"):
        mvr.render(size=(32, 32), sky="environment")
