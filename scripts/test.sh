#!/usr/bin/env bash
# Quick start (b): install what is missing, build, run the whole test suite. Builds the micro
# benchmarks too (MVR_BUILD_BENCH): ctest runs each once (MicroBench.Smoke) so they do not rot,
# and the Python module (MVR_BUILD_PYTHON, build/python/mvr): pytest runs python/tests after ctest
# (with Debian's /usr/bin/python3; no tests collected, pytest's exit 5, fails too).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh -DMVR_BUILD_BENCH=ON -DMVR_BUILD_PYTHON=ON
export MVR_SHARED_DIR="${MVR_SHARED_DIR:-$(cd .. && pwd)/shared}"
cd build
ctest --output-on-failure --timeout 900 -j"$(nproc)" "$@"
cd ..
MVR_CLI="$PWD/build/tools/cli/mvr" PYTHONPATH="$PWD/build/python" \
    /usr/bin/python3 -m pytest -q -p no:cacheprovider python/tests
