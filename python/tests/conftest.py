"""Shared fixtures of the mvr Python tests: the `mvr` command line and a small model file."""
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


def find_cli():
    """The `mvr` tool the arrays are checked against: $MVR_CLI, the CMake build, the pip build,
    or `mvr` on PATH."""
    for candidate in (os.environ.get("MVR_CLI"), ROOT / "build" / "tools" / "cli" / "mvr",
                      ROOT / "build" / "python-pip" / "tools" / "cli" / "mvr", shutil.which("mvr")):
        if candidate and Path(candidate).is_file() and os.access(candidate, os.X_OK):
            return str(candidate)
    return None


@pytest.fixture(scope="session")
def cli():
    path = find_cli()
    if path is None:
        pytest.fail("the mvr tool was not found (set MVR_CLI, or build it: scripts/build.sh)")
    def run(*args):
        done = subprocess.run([path, *map(str, args)], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return done.stdout
    run.path = path
    return run


@pytest.fixture(scope="session")
def model(tmp_path_factory):
    """A small OBJ: a square pyramid (5 vertices, 6 triangles)."""
    path = tmp_path_factory.mktemp("model") / "pyramid.obj"
    path.write_text("v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nv 0 1.5 0\n"
                    "f 1 2 3\nf 1 3 4\nf 1 5 2\nf 2 5 3\nf 3 5 4\nf 4 5 1\n")
    return path


def read_png(path):
    """RGBA uint8 (H, W, 4) of a PNG, through Pillow (a dependency of matplotlib)."""
    from PIL import Image
    with Image.open(path) as im:
        return np.asarray(im.convert("RGBA"))
