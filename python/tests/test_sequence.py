"""mvr.render_sequence(): one RenderResult per frame, and the frame folders `mvr render --frames`
writes, byte for byte (session::writeFrameFolder is the one writer of both)."""
import numpy as np
import pytest

import mvr
from conftest import read_png


def test_orbit_equals_cli(cli, tmp_path):
    cli("render", "--views", "2", "--size", "48x32", "--orbit", "90", "--frames", "3", "--depth",
        "--format", "sbs", "-q", "-o", tmp_path / "cli")
    seq = mvr.render_sequence(views=2, size=(48, 32), orbit=90, frames=3, depth=True,
                              format="sbs", output=tmp_path / "py")
    assert len(seq) == 3 and seq.frames == [0, 1, 2]
    results = list(seq)
    assert [r.frame for r in results] == [0, 1, 2]
    folders = sorted(p.name for p in (tmp_path / "cli").iterdir())
    assert folders == ["frame-0000", "frame-0001", "frame-0002"]
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == folders
    for r, folder in zip(results, folders):
        names = sorted(p.name for p in (tmp_path / "cli" / folder).iterdir())
        assert "anaglyph.png" in names  # a stereo pair's frame, as a still
        assert sorted(p.name for p in (tmp_path / "py" / folder).iterdir()) == names
        for name in names:
            assert (tmp_path / "py" / folder / name).read_bytes() == \
                (tmp_path / "cli" / folder / name).read_bytes(), (folder, name)
        for v in range(2):
            np.testing.assert_array_equal(r.color[v], read_png(tmp_path / "cli" / folder / f"view-{v}.png"))
        np.testing.assert_array_equal(r.composites["sbs"], read_png(tmp_path / "cli" / folder / "sbs.png"))
    assert not np.array_equal(results[0].color, results[2].color)  # the orbit moves the camera


def test_range_shard_and_still(tmp_path):
    seq = mvr.render_sequence(size=(16, 12), frames=6, frame_range="1:5", shard="0/2")
    assert seq.frames == [2, 4]
    first = next(iter(seq))
    assert first.frame == 2 and first.color.shape == (2, 12, 16, 4)
    assert mvr.render(size=(16, 12)).frame is None
    # Frame 0 of an orbit is the still render.
    zero = next(mvr.render_sequence(size=(16, 12), frames=2, orbit=30))
    np.testing.assert_array_equal(zero.color, mvr.render(size=(16, 12)).color)


def test_sequence_errors(tmp_path):
    with pytest.raises(ValueError, match="--frames 0 is out of range"):
        mvr.render_sequence(size=(16, 12))
    with pytest.raises(ValueError, match="--frame-range '5:2' is out of range"):
        mvr.render_sequence(size=(16, 12), frames=3, frame_range="5:2")
    with pytest.raises(ValueError, match="exclude each other"):
        mvr.render_sequence(size=(16, 12), frames=3, orbit=10, camera_path=tmp_path / "p.json")
    with pytest.raises(FileNotFoundError, match="file not found"):
        mvr.render_sequence(size=(16, 12), camera_path=tmp_path / "p.json")
    with pytest.raises(mvr.ParameterError):
        mvr.render(size=(16, 12), frames=3)  # a sequence's keyword
    with pytest.raises(mvr.ParameterError):
        mvr.render_sequence(size=(16, 12), frames="three")
