#!/usr/bin/env bash
# Quick start (b): install what is missing, build, run the whole test suite. Builds the micro
# benchmarks too (MVR_BUILD_BENCH): ctest runs each once (MicroBench.Smoke) so they do not rot.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh -DMVR_BUILD_BENCH=ON
export MVR_SHARED_DIR="${MVR_SHARED_DIR:-$(cd .. && pwd)/shared}"
cd build
ctest --output-on-failure --timeout 900 -j"$(nproc)" "$@"
