#!/usr/bin/env bash
# Sequences over MPI ranks, with a real mpirun: a 24-frame turntable of a 48-view quilt into
# MKV with 2 ranks equals the one-process run byte for byte; one frame's views split over
# 4 ranks equal it too; a rank killed mid-run stops the run with an error on rank 0 and no
# video under its final name. Usage: mpi_test.sh MVR HAVE_MPI. Exit 77 (skipped) without
# mpirun or an mvr built without MPI.
set -euo pipefail
mvr=$1
if [[ ${2:-0} != 1 && ${2:-0} != ON && ${2:-0} != TRUE ]]; then
    echo "mpi_test: SKIPPED: this mvr was built without MPI (libopenmpi-dev)"; exit 77
fi
command -v mpirun >/dev/null || { echo "mpi_test: SKIPPED: no mpirun (openmpi-bin)"; exit 77; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# Two cores for many ranks: no busy polling fights, no network interfaces needed.
export OMPI_MCA_mpi_yield_when_idle=1 OMPI_MCA_btl=self,vader OMPI_MCA_rmaps_base_oversubscribe=1
# When a rank dies, mpirun sends the others SIGCONT, SIGTERM 1 s later and SIGKILL 1 s after
# that. On a loaded machine (ctest -j2 beside 3 ranks) rank 0 sometimes got no CPU time in that
# second and was killed before its SIGTERM handler could print its line (1 run in 8 with 8
# busy loops beside it; none of 25 with 4 s). A user's own setting wins.
export OMPI_MCA_odls_base_sigkill_timeout=${OMPI_MCA_odls_base_sigkill_timeout:-5}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
run() { mpirun -n "$1" --oversubscribe "${@:2}"; }

video=0
"$mvr" render --frames 1 --size 32x24 -q --video "$tmp/probe.mkv" -o "$tmp/probe" 2>/dev/null && video=1
quilt=(--views 48 --size 64x48 --orbit 360 --frames 24 --format quilt -q)
# The frames' folders too (a video alone is written by default).
w=(--write views,composites,video)
[[ $video == 1 ]] && one=("${w[@]}" --video "$tmp/one/quilt.mkv") two=("${w[@]}" --video "$tmp/two/quilt.mkv") || one=() two=()
"$mvr" render "${quilt[@]}" "${one[@]}" -o "$tmp/one"
run 2 "$mvr" render "${quilt[@]}" "${two[@]}" -o "$tmp/two"
diff -r "$tmp/one" "$tmp/two" || fail "mpirun -n 2 differs from one process"
[[ $(ls "$tmp/two" | grep -c '^frame-') == 24 ]] || fail "expected 24 frames"
if [[ $video == 1 ]] && command -v ffprobe >/dev/null; then
    n=$(ffprobe -v error -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$tmp/two/quilt.mkv")
    [[ $n == 24 ]] || fail "quilt.mkv has $n frames"
fi

# One frame, 48 views over 4 ranks (3 workers): the views are split and gathered on rank 0.
single=(--views 48 --size 64x48 --frames 1 --format quilt -q)
"$mvr" render "${single[@]}" -o "$tmp/s1"
run 4 "$mvr" render "${single[@]}" -o "$tmp/s4"
diff -r "$tmp/s1" "$tmp/s4" || fail "one frame over 4 ranks differs"

# 3 ranks, 5 frames of 2 views: the dynamic queue with more workers than... a few frames each.
run 3 "$mvr" render --views 2 --size 32x24 --orbit 90 --frames 5 -q -o "$tmp/q3"
"$mvr" render --views 2 --size 32x24 --orbit 90 --frames 5 -q -o "$tmp/q1"
diff -r "$tmp/q1" "$tmp/q3" || fail "3 ranks differ"

# An animated glTF (nodes and camera) with --depth: frames over 3 ranks, and one frame's views
# split over 4 ranks, equal the one-process run (depth images gathered too).
python3 "$(dirname "$0")/animated_gltf.py" "$tmp/anim.gltf"
anim=(--size 48x48 -q --fps 4 --depth)
"$mvr" render "$tmp/anim.gltf" "${anim[@]}" --views 3 --frames 6 -o "$tmp/a1"
run 3 "$mvr" render "$tmp/anim.gltf" "${anim[@]}" --views 3 --frames 6 -o "$tmp/a3"
diff -r "$tmp/a1" "$tmp/a3" || fail "an animated glTF over 3 ranks differs from one process"
[[ -f $tmp/a3/frame-0005/depth-2.png ]] || fail "no depth image gathered under MPI"
"$mvr" render "$tmp/anim.gltf" "${anim[@]}" --frames 1 --views 9 -o "$tmp/d1"
run 4 "$mvr" render "$tmp/anim.gltf" "${anim[@]}" --frames 1 --views 9 -o "$tmp/d4"
diff -r "$tmp/d1" "$tmp/d4" || fail "one frame's views and depth over 4 ranks differ"
[[ $(ls "$tmp/d4/frame-0000" | grep -c '^depth-') == 9 ]] || fail "expected 9 depth images"

# A rank killed mid-run: an error line from rank 0, a non-zero exit, no video under its name.
long=(--views 48 --size 128x96 --orbit 360 --frames 400 --format quilt -q)
[[ $video == 1 ]] && long+=(--write composites,video --video "$tmp/k/quilt.mkv")
set +e
run 3 "$mvr" render "${long[@]}" -o "$tmp/k" >"$tmp/k.log" 2>&1 &
job=$!
for _ in $(seq 300); do [[ -d $tmp/k/frame-0001 ]] && break; sleep 0.1; done
killed=0
for p in $(pgrep -f -- "-o $tmp/k"); do
    r=$(tr '\0' '\n' </proc/"$p"/environ 2>/dev/null | sed -n 's/^OMPI_COMM_WORLD_RANK=//p')
    if [[ $r == 2 ]]; then kill -9 "$p"; killed=1; fi
done
wait $job
rc=$?
set -e
[[ $killed == 1 ]] || fail "found no rank 2 to kill"
[[ $rc != 0 ]] || fail "the run with a killed rank exited 0"
grep -q "^error: .*rank" "$tmp/k.log" || fail "no error line naming the stopped rank: $(cat "$tmp/k.log")"
[[ ! -e $tmp/k/quilt.mkv ]] || fail "a video was left under its final name"
[[ -z $(ls "$tmp/k" | grep '\.part\.mkv$' || true) ]] || fail "the unfinished video was left"
# Only whole frames: no unfinished frame folder (.part) or staging folder (.mvr-part-*) is left,
# and the line says how many frames are complete.
[[ -z $(ls -a "$tmp/k" | grep 'part' || true) ]] || fail "left unfinished: $(ls -a "$tmp/k" | grep part)"
grep -q "frames are complete in $tmp/k/\|no frame was complete" "$tmp/k.log" ||
    fail "the error line does not say what is left: $(cat "$tmp/k.log")"
echo "mpi_test: ok"
