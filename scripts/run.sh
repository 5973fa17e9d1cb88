#!/usr/bin/env bash
# Quick start (a): install what is missing, build, render the default scene into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
build/tools/cli/mvr render -o out "$@"
