"""The example script renders a quilt and writes its figure when there is no display."""
import os
import subprocess
import sys
from pathlib import Path

import mvr

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "quilt.py"


def test_quilt_example_writes_its_figure(tmp_path):
    out = tmp_path / "figure.png"
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    # the mvr these tests import, wherever it came from (PYTHONPATH may be relative)
    env["PYTHONPATH"] = os.pathsep.join([str(Path(mvr.__file__).resolve().parents[1]),
                                         env.get("PYTHONPATH", "")])
    done = subprocess.run([sys.executable, str(EXAMPLE), "--size", "96x72", "--out", str(out)],
                          capture_output=True, text=True, env=env, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "9 views of 96x72" in done.stdout
