#!/bin/sh
# `mvr bench views`, the README's "Many views": rows of 1..100 views of 420x560, vertex lighting.
#  1. the soft methods on the 9-bunny scene (625k triangles): bench/results/views.{md,json},
#     bench/views.png;
#  2. the gl methods (llvmpipe here) on one bunny (69k triangles; the 625k scene takes minutes a
#     frame at 100 views there): bench/results/views-gl.{md,json}, bench/views-gl.png;
#  3. the stereo pair and the 3x3 grid at 1024x768 (soft, 625k): bench/results/views-1024.md.
# The soft sweeps run in rounds (--rounds: every count measured once per round, the rounds'
# frames pooled), so that a change in the load of a shared machine hits every count alike.
# Usage: bench/run_views.sh [MVR]   (run it on a quiet machine)
set -e
here=$(cd "$(dirname "$0")" && pwd)
mvr=${1:-$here/../build/tools/cli/mvr}
out=$here/results
mkdir -p "$out"
nice -n 10 "$mvr" bench views stanford-bunny.obj --grid 9 --counts 1,2,4,9,16,45,72,100 \
    --size 420x560 --rounds 3 --frames 3 --warmup 1 --progress \
    --methods soft:multipass,soft:unified \
    --save-json "$out/views.json" --plot "$here/views.png" > "$out/views.md"
nice -n 10 "$mvr" bench views stanford-bunny.obj --counts 1,2,9,16,45,100 \
    --size 420x560 --frames 3 --warmup 1 --progress \
    --methods gl:multipass,gl:instanced-layer,gl:gs-layered,gl:viewport-array \
    --save-json "$out/views-gl.json" --plot "$here/views-gl.png" > "$out/views-gl.md"
nice -n 10 "$mvr" bench views stanford-bunny.obj --grid 9 --grid-views 1x1,2x1,3x3 \
    --size 1024x768 --rounds 5 --frames 3 --warmup 1 --progress \
    --methods soft:multipass,soft:unified \
    > "$out/views-1024.md"
