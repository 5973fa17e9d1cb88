#!/usr/bin/env bash
# Frames per second of a sequence for 1 and 2 MPI ranks (and the gather's share), the threads
# per rank chosen so that ranks do not fight over cores (mvr's --threads default under mpirun:
# the cores divided by the ranks on the node). Run on a quiet machine.
# Usage: scripts/bench-sequence.sh [MVR] [FRAMES] [extra mvr render options...]
# Default: a 24-frame turntable of a 48-view quilt of 64x48 views.
set -euo pipefail
mvr=${1:-build/tools/cli/mvr}
frames=${2:-24}
shift $(($# > 2 ? 2 : $#))
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
args=(--views 48 --size 64x48 --orbit 360 --frames "$frames" --format quilt -q "$@")
now() { date +%s.%N; }
measure() {  # label command...
    local t0 t1
    rm -rf "$tmp/out"
    t0=$(now)
    "${@:2}" -o "$tmp/out" >/dev/null
    t1=$(now)
    awk -v l="$1" -v n="$frames" -v a="$t0" -v b="$t1" \
        'BEGIN { printf "| %-28s | %8.2f | %8.2f |\n", l, b - a, n / (b - a) }'
}
echo "| run | seconds | frames/s |"
echo "|---|---:|---:|"
measure "1 process" "$mvr" render "${args[@]}"
if command -v mpirun >/dev/null; then
    measure "mpirun -n 2 (1 worker)" mpirun -n 2 --oversubscribe "$mvr" render "${args[@]}"
    measure "mpirun -n 3 (2 workers)" mpirun -n 3 --oversubscribe "$mvr" render "${args[@]}"
fi
