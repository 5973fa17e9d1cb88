#!/bin/sh
# Runs the three paper benches one after the other (never two at once) at low priority and
# writes their tables (.md), JSON and plots into bench/. Usage: bench/run_papers.sh [MVR]
# (MVR: the mvr binary, default build/tools/cli/mvr). Progress lines go to stderr.
set -e
here=$(cd "$(dirname "$0")" && pwd)
mvr=${1:-$here/../build/tools/cli/mvr}
out=$here/results
mkdir -p "$out"
nice -n 10 "$mvr" bench sorbier --frames 9 --warmup 1 --progress \
    --save-json "$out/sorbier.json" --plot "$here/sorbier.png" > "$out/sorbier.md"
nice -n 10 "$mvr" bench kalaiah --frames 7 --warmup 1 --progress \
    --save-json "$out/kalaiah.json" --plot "$here/kalaiah.png" > "$out/kalaiah.md"
nice -n 10 "$mvr" bench adelson --frames 15 --warmup 2 --min-batch-ms 50 --progress \
    --save-json "$out/adelson.json" --plot "$here/adelson.png" > "$out/adelson.md"
