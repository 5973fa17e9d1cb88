"""Builds the `mvr` Python package with CMake (MVR_BUILD_PYTHON) and installs it.

    /usr/bin/python3 -m venv --system-site-packages .venv && . .venv/bin/activate
    pip install --no-build-isolation .

The C++ build goes to build/python-pip (or $MVR_CMAKE_BUILD_DIR); its `mvr` tool is built too,
for the tests. Extra CMake arguments: $MVR_CMAKE_ARGS.
"""
import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = Path(os.environ.get("MVR_CMAKE_BUILD_DIR", ROOT / "build" / "python-pip"))
        pkg = build / "python" / "mvr"
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
            "-DMVR_BUILD_PYTHON=ON", "-DMVR_BUILD_TESTS=OFF", "-DMVR_BUILD_VIEWER=OFF",
            f"-DPython3_EXECUTABLE={sys.executable}",
        ] + shlex.split(os.environ.get("MVR_CMAKE_ARGS", ""))
        if shutil.which("ccache"):
            configure += ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache", "-DCMAKE_C_COMPILER_LAUNCHER=ccache"]
        subprocess.check_call(configure)
        subprocess.check_call(["cmake", "--build", str(build), "-j", str(os.cpu_count() or 2),
                               "--target", "mvr_python", "mvr"])
        out = Path(self.get_ext_fullpath(ext.name))
        out.parent.mkdir(parents=True, exist_ok=True)
        built = next(pkg.glob("_core*.so"))
        shutil.copyfile(built, out)


setup(
    name="mvr",
    version="0.1.0",
    description="Multi-view (stereo, light-field) rendering: the mvr library from Python",
    packages=["mvr"],
    package_dir={"mvr": "python/mvr"},
    package_data={"mvr": ["py.typed", "*.pyi"]},
    ext_modules=[Extension("mvr._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    python_requires=">=3.9",
    install_requires=["numpy"],
    zip_safe=False,
)
