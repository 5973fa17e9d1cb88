#!/usr/bin/env bash
# Sequences end to end: frame folders, --frame-range, --shard shares adding up to the whole,
# video files read back with ffprobe (frame count, size, codec, StereoMode), refusals.
# Usage: sequence_test.sh MVR
set -euo pipefail
mvr=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
common=(--views 4 --size 32x24 --orbit 360 --frames 6 -q --format quilt --quilt 2x2)

"$mvr" render "${common[@]}" -o "$tmp/whole"
[[ $(ls "$tmp/whole" | grep -c '^frame-') == 6 ]] || fail "expected 6 frame folders"
[[ -f $tmp/whole/frame-0005/view-3.png ]] || fail "no frame-0005/view-3.png"
ls "$tmp/whole/frame-0002" | grep -q '^quilt' || fail "no quilt in frame-0002"
cmp -s "$tmp/whole/frame-0000/view-0.png" "$tmp/whole/frame-0001/view-0.png" &&
    fail "the orbit does not move the camera"
[[ -z $(ls "$tmp/whole" | grep '\.part$' || true) ]] || fail "a .part folder was left"

# Writing beside rendering (issue 37): the same bytes whether each frame's files are written on
# their own thread while the next frame renders (the default), with a deeper queue, or one
# frame at a time on the rendering thread (MVR_WRITE_QUEUE=0, the order before).
MVR_WRITE_QUEUE=0 "$mvr" render "${common[@]}" --depth -o "$tmp/serial"
MVR_WRITE_QUEUE=3 "$mvr" render "${common[@]}" --depth -o "$tmp/deep"
"$mvr" render "${common[@]}" --depth -o "$tmp/overlap"
diff -r "$tmp/serial" "$tmp/overlap" || fail "frames written beside rendering differ"
diff -r "$tmp/serial" "$tmp/deep" || fail "frames written through a deeper queue differ"

# --shard I/N: the shares add up to the whole, byte for byte.
for i in 0 1 2; do "$mvr" render "${common[@]}" --shard $i/3 -o "$tmp/shards"; done
diff -r "$tmp/whole" "$tmp/shards" || fail "--shard shares differ from the whole"
"$mvr" render "${common[@]}" --shard 1/4 -o "$tmp/one"
[[ $(ls "$tmp/one" | tr '\n' ' ') == "frame-0001 frame-0005 " ]] || fail "--shard 1/4 frames: $(ls "$tmp/one")"

# --frame-range A:B
"$mvr" render "${common[@]}" --frame-range 2:4 -o "$tmp/range"
[[ $(ls "$tmp/range" | tr '\n' ' ') == "frame-0002 frame-0003 " ]] || fail "--frame-range 2:4: $(ls "$tmp/range")"
diff -r "$tmp/range/frame-0003" "$tmp/whole/frame-0003" || fail "--frame-range frame differs"

# A stereo pair's frames hold the anaglyph.png a still render writes (session::writeOutputs is
# the one writer of both): Dubois' red-cyan of the frame's two views.
"$mvr" render --views 2 --size 32x24 --orbit 90 --frames 2 -q -o "$tmp/pair"
for f in 0000 0001; do
    [[ -f $tmp/pair/frame-$f/anaglyph.png ]] || fail "no frame-$f/anaglyph.png in a stereo sequence"
    "$mvr" compose "$tmp/pair/frame-$f/view-0.png" "$tmp/pair/frame-$f/view-1.png" \
        -f anaglyph-dubois -q -o "$tmp/pair-$f.png"
    cmp -s "$tmp/pair/frame-$f/anaglyph.png" "$tmp/pair-$f.png" ||
        fail "frame-$f/anaglyph.png is not the anaglyph of its views"
done
"$mvr" render --views 2 --size 32x24 -q -o "$tmp/pair-still"
diff -r "$tmp/pair/frame-0000" "$tmp/pair-still" || fail "frame 0 of an orbit differs from a still"
[[ ! -e $tmp/whole/frame-0000/anaglyph.png ]] || fail "an anaglyph for 4 views"

# The stereo surfaces (--sky, --label) are drawn into every frame of a sequence, as into a
# single render: frame 3 of the sequence equals the single render of that frame's camera.
"$mvr" render "${common[@]}" --sky gradient --label "HI@0.5,0.5" -o "$tmp/sky"
cmp -s "$tmp/sky/frame-0003/view-1.png" "$tmp/whole/frame-0003/view-1.png" &&
    fail "--sky/--label were not drawn into the frames of a sequence"
"$mvr" render "${common[@]}" --sky gradient --label "HI@0.5,0.5" --frame-range 3:4 -o "$tmp/sky3"
diff -r "$tmp/sky/frame-0003" "$tmp/sky3/frame-0003" || fail "--sky frame differs by range"

# A camera path (docs/animation.md)
cat >"$tmp/path.json" <<'JSON'
{"keys": [{"time": 0, "position": [0, 0, 6], "target": [0, 0, 0], "fov": 40},
          {"time": 1, "position": [3, 1, 5], "target": [0, 0, 0]}]}
JSON
"$mvr" render --views 2 --size 32x24 -q --camera-path "$tmp/path.json" --fps 4 -o "$tmp/path"
[[ $(ls "$tmp/path" | grep -c '^frame-') == 5 ]] || fail "camera path of 1 s at 4 fps: 5 frames"

# A glTF file's animation (docs/animation.md): nodes (LINEAR, STEP, a parent and its child)
# and the camera move with t = frame / fps; past the last key the last one holds; the shares
# add up to the whole; --orbit wins over the file's animated camera (the nodes still move).
python3 "$(dirname "$0")/animated_gltf.py" "$tmp/anim.gltf"
anim=(--views 3 --size 48x48 -q --frames 8 --fps 4)
"$mvr" render "$tmp/anim.gltf" "${anim[@]}" -o "$tmp/anim"
[[ $(ls "$tmp/anim" | grep -c '^frame-') == 8 ]] || fail "animated glTF: expected 8 frames"
cmp -s "$tmp/anim/frame-0000/view-1.png" "$tmp/anim/frame-0002/view-1.png" &&
    fail "the glTF animation does not move anything"
# frames 4..7 are at t = 1, 1.25, 1.5, 1.75 s: past the last key (1 s) everything holds.
for f in 5 6 7; do
    diff -r "$tmp/anim/frame-0004" "$tmp/anim/frame-000$f" >/dev/null ||
        fail "frame $f past the animation's end differs from frame 4 (the last key holds)"
done
for i in 0 1; do "$mvr" render "$tmp/anim.gltf" "${anim[@]}" --shard $i/2 -o "$tmp/anim-sh"; done
diff -r "$tmp/anim" "$tmp/anim-sh" || fail "animated glTF: --shard shares differ from the whole"
"$mvr" render "$tmp/anim.gltf" "${anim[@]}" --orbit 90 -o "$tmp/anim-orbit"
cmp -s "$tmp/anim-orbit/frame-0002/view-1.png" "$tmp/anim/frame-0002/view-1.png" &&
    fail "--orbit did not take over from the file's animated camera"

# Refusals: one error line, non-zero exit.
expect_error() {
    local want=$1; shift
    if out=$("$mvr" render "$@" 2>&1); then fail "accepted: $*"; fi
    grep -q "^error: .*$want" <<<"$out" || fail "for $*: expected '$want', got: $out"
}
expect_error "--frame-range" --frames 4 --frame-range 3:9 -o "$tmp/bad"
expect_error "--shard" --frames 4 --shard 4/4 -o "$tmp/bad"
expect_error "--frames" --frames 2000000 --orbit 90 -o "$tmp/bad"
echo '{"keys": [{"time": 1, "position": [0,0,5], "target": [0,0,0]}, {"time": 0.5, "position": [0,0,6], "target": [0,0,0]}]}' >"$tmp/back.json"
expect_error "key 1" --camera-path "$tmp/back.json" -o "$tmp/bad"

# Video (when this mvr has FFmpeg and ffprobe is here).
if "$mvr" render --frames 1 --size 32x24 -q --video "$tmp/probe.mkv" -o "$tmp/probe" 2>/dev/null &&
    command -v ffprobe >/dev/null; then
    probe() { ffprobe -v error -count_frames -select_streams v:0 -show_entries \
        "stream=codec_name,width,height,nb_read_frames:stream_tags=stereo_mode:stream_side_data=type" \
        -of default=nw=1 "$1"; }
    "$mvr" render --views 2 --size 32x24 --orbit 360 --frames 5 -q --format sbs --video "$tmp/sbs.mkv" -o "$tmp/v"
    p=$(probe "$tmp/sbs.mkv")
    for want in codec_name=h264 width=64 height=24 nb_read_frames=5 TAG:stereo_mode=left_right; do
        grep -qx "$want" <<<"$p" || fail "sbs.mkv: no $want in: $p"
    done
    # A video alone by default; --write adds the frames' folders, and must keep the video.
    [[ -z $(ls "$tmp/v" | grep '^frame-' || true) ]] || fail "a video alone wrote frame folders"
    "$mvr" render --views 2 --size 32x24 --frames 2 -q --format sbs --write views,composites,video \
        --video "$tmp/w.mkv" -o "$tmp/w"
    [[ -f $tmp/w/frame-0001/sbs.png && -f $tmp/w/frame-0001/view-1.png ]] ||
        fail "--write views,composites,video wrote no frames"
    [[ $(probe "$tmp/w.mkv") == *nb_read_frames=2* ]] || fail "w.mkv: expected 2 frames"
    expect_error "leaves the video out" --frames 2 --write views --video "$tmp/w2.mkv" -o "$tmp/w2"
    "$mvr" render --views 2 --size 32x24 --frames 3 -q --format tb --video "$tmp/tb.mp4" -o "$tmp/v"
    p=$(probe "$tmp/tb.mp4")
    for want in width=32 height=48 nb_read_frames=3 "type=top and bottom"; do
        grep -qx "$want" <<<"$p" || fail "tb.mp4: no $want in: $p"
    done
    "$mvr" render --views 3 --size 32x24 --frames 2 -q --video "$tmp/views.mkv" -o "$tmp/v"
    [[ $(ffprobe -v error -show_entries stream=index -of csv=p=0 "$tmp/views.mkv" | wc -l) == 3 ]] ||
        fail "views.mkv: expected 3 streams"
    # The codecs: each file read back by ffprobe, with the stereo tag of side by side.
    for c in h265:hevc av1:av1; do
        "$mvr" render --views 2 --size 64x64 --frames 2 -q --format sbs --codec "${c%%:*}" \
            --video "$tmp/c-${c%%:*}.mkv" -o "$tmp/c"
        p=$(probe "$tmp/c-${c%%:*}.mkv")
        for want in "codec_name=${c#*:}" width=128 height=64 nb_read_frames=2 TAG:stereo_mode=left_right; do
            grep -qx "$want" <<<"$p" || fail "${c%%:*}: no $want in: $p"
        done
    done
    # ffv1 is lossless: its frames decode to the PNGs' pixels, bit for bit (odd sizes too).
    "$mvr" render --views 2 --size 33x25 --frames 3 --orbit 30 -q --format sbs --codec ffv1 \
        --write composites,video --video "$tmp/l.mkv" -o "$tmp/l"
    ffmpeg -v error -i "$tmp/l.mkv" -f rawvideo -pix_fmt rgba "$tmp/l.rgba"
    ffmpeg -v error -i "$tmp/l/frame-%04d/sbs.png" -f rawvideo -pix_fmt rgba "$tmp/p.rgba"
    [[ -s $tmp/p.rgba ]] && cmp "$tmp/l.rgba" "$tmp/p.rgba" || fail "ffv1 frames differ from the PNGs"
    # The same video and frames with the writes beside the rendering and one frame at a time.
    for q in 0 1; do
        MVR_WRITE_QUEUE=$q "$mvr" render --views 4 --size 33x25 --frames 5 --orbit 40 -q \
            --format quilt --quilt 2x2 --codec ffv1 --write views,composites,video \
            --video "$tmp/q$q.mkv" -o "$tmp/q$q"
    done
    cmp "$tmp/q0.mkv" "$tmp/q1.mkv" || fail "the ffv1 video differs with the writes overlapped"
    diff -r "$tmp/q0" "$tmp/q1" || fail "the video's frames differ with the writes overlapped"
    ffmpeg -v error -i "$tmp/q1.mkv" -f rawvideo -pix_fmt rgba "$tmp/q1.rgba"
    ffmpeg -v error -i "$tmp/q1/frame-%04d/quilt_qs2x2a1.32.png" -f rawvideo -pix_fmt rgba "$tmp/q1p.rgba"
    [[ -s $tmp/q1p.rgba ]] && cmp "$tmp/q1.rgba" "$tmp/q1p.rgba" ||
        fail "the overlapped ffv1 video's frames differ from its PNGs (in order)"
    expect_error "--codec ffv1: lossless FFV1 goes in a .mkv file" --frames 2 --codec ffv1 --video "$tmp/l.mp4" -o "$tmp/bad"
    expect_error "--codec vp9: unknown codec" --frames 2 --codec vp9 --video "$tmp/x.mkv" -o "$tmp/bad"
    expect_error "--crf 52 is out of range for h264 (expected 0..51)" --frames 2 --crf 52 --video "$tmp/x.mkv" -o "$tmp/bad"
    expect_error "--codec av1: libsvtav1 needs frames of at least 64x64" --size 32x24 --frames 2 --codec av1 --video "$tmp/x.mkv" -o "$tmp/bad"
    expect_error "--encoder-preset warp: libx264 refused it" --size 32x24 --frames 2 --encoder-preset warp --video "$tmp/x.mkv" -o "$tmp/bad"
    # A quilt video named without the layout: a warning with the name players read.
    out=$("$mvr" render --views 4 --size 32x24 --frames 1 -q --format quilt --quilt 2x2 --video "$tmp/q.mkv" -o "$tmp/q" 2>&1)
    grep -q "^warning: --video $tmp/q.mkv: .*call it q_qs2x2a1.3333.mkv" <<<"$out" || fail "no quilt name warning: $out"
    expect_error "even width" --size 33x24 --frames 2 --video "$tmp/odd.mkv" -o "$tmp/odd"
    [[ -z $(ls "$tmp/odd" 2>/dev/null) ]] || fail "a refused video still rendered frames"
    expect_error ".mkv or .mp4" --frames 2 --video "$tmp/x.avi" -o "$tmp/bad"
    [[ -z $(ls "$tmp" | grep '\.part\.' || true) ]] || fail "a .part video was left"
else
    echo "sequence_test: no FFmpeg in this mvr or no ffprobe: video checks skipped"
fi
echo "sequence_test: ok"
