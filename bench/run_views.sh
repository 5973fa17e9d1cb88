#!/bin/sh
# `mvr bench views` on the 9-bunny scene (625k triangles): rows of 1..100 views of 420x560, the
# soft methods and the gl ones that batch, at low priority; writes bench/results/views.{md,json}
# and bench/views.png (the README's "Many views"). Usage: bench/run_views.sh [MVR]
set -e
here=$(cd "$(dirname "$0")" && pwd)
mvr=${1:-$here/../build/tools/cli/mvr}
out=$here/results
mkdir -p "$out"
nice -n 10 "$mvr" bench views stanford-bunny.obj --grid 9 --counts 1,2,4,9,16,45,72,100 \
    --size 420x560 --frames 7 --warmup 1 --progress \
    --methods soft:multipass,soft:unified,gl:multipass,gl:instanced-layer,gl:gs-layered,gl:viewport-array \
    --save-json "$out/views.json" --plot "$here/views.png" > "$out/views.md"
