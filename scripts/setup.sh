#!/usr/bin/env bash
# Installs what mvr needs on Debian 12 (idempotent: installs only what is missing).
# Run as root, or with sudo available. Every dependency of the build, the tests and the
# benchmarks is listed here and nowhere else.
set -euo pipefail

packages=(
    # toolchain
    build-essential cmake pkg-config git
    # fuzzers (libFuzzer, ASan + UBSan runtimes) and readable sanitizer stacks
    clang libclang-rt-14-dev llvm
    # libraries
    libglm-dev libfmt-dev libcli11-dev nlohmann-json3-dev
    libpng-dev libjpeg-dev libopenexr-dev libstb-dev
    libassimp-dev libmeshoptimizer-dev
    libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev
    # a second GL driver for the tests: zink over lavapipe (Mesa's Vulkan drivers)
    mesa-vulkan-drivers
    # the vk backend: the Vulkan loader and headers, glslc (shaders to SPIR-V at build time) and
    # the validation layers every vk test runs with
    libvulkan-dev glslc vulkan-validationlayers
    # sequences: video files (FFmpeg's libraries, ffprobe for the tests) and MPI (Open MPI)
    ffmpeg libavcodec-dev libavformat-dev libswscale-dev libavutil-dev
    libopenmpi-dev openmpi-bin
    # tests and benchmarks
    googletest libgtest-dev libbenchmark-dev
    xvfb xauth libimage-exiftool-perl gnuplot-nox
    # the Python module (import mvr) and its tests
    python3-dev python3-venv python3-pip python3-setuptools python3-wheel
    pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib
)

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
    sudo=""
    [[ $(id -u) -eq 0 ]] || sudo="sudo"
    echo "setup: installing ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
    echo "setup: all ${#packages[@]} packages present"
fi
