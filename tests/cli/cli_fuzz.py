#!/usr/bin/python3
"""CLI-level fuzz of `mvr render` and `mvr compose` (issue 44 item 6): the all-or-nothing contract.

Seeded and deterministic: case i of seed S is the same command, files and mutations on every
machine (random.Random("S:i")), whatever the number of parallel jobs. Each case starts from a
valid command (a still, a sequence, a display preset, a compose of small PNGs), mutates it (options
dropped, repeated, swapped or added; values replaced by nonsense; inputs made empty, truncated, a
directory, a FIFO, /dev/zero; outputs under a regular file, onto an existing directory, through a
/dev/full symlink) and runs it in a folder of its own, killed after --timeout seconds.

A case fails on:
  hang            no exit within --timeout seconds (SIGKILLed)
  signal          killed by a signal (or an exit status >= 128)
  bad-exit-code   an exit status other than 0..5 (README: 1 usage, 2 input, 3 unsupported,
                  4 output, 5 internal)
  error-format    a failed run whose stderr is not one line `error: ...`, optionally followed by
                  one line "run `mvr --help` ..."
  noise-before-error  the same, but `warning: ` / `note: ` / progress lines came before it
  stderr-on-success  an exit 0 whose stderr holds a line other than `warning: `, `note: ` or a
                  sequence's progress
  unreadable-number  an error message with a run of 40+ digits the command line did not hold
  files-changed   a failed run that left its folder (the -o directory or file, --report-json,
                  --video, the inputs) different from before: names, types, sizes, bytes
  temp-left       a file left in the run's TMPDIR, or a *.part / *.tmp name after a success
With --oracles, two more (heuristics for the refusal table; not part of the default run):
  accepted-nonsense  exit 0 with a value that is never valid for its option (nan, '', 'abc', ...)
  exit-code       a case whose one mutation is an input file (expect 2), an output path (expect 4)
                  or a nonsense option value (expect 1) exits with another code

Usage: cli_fuzz.py MVR [--seed 44] [--cases 300] [--jobs N] [--timeout 10] [--only I,J]
                       [--keep] [--oracles] [-v]
Exit 0 when every case passed, 1 with a summary of the failure kinds (one reproduction each:
the command, the files set up, exit status, stderr and the files changed), 2 on a set-up error.
Reproduce one case: cli_fuzz.py MVR --seed S --only I --keep (its folder is printed and kept).
"""

import argparse
import concurrent.futures
import hashlib
import os
import random
import re
import shlex
import shutil
import signal
import stat
import struct
import subprocess
import sys
import tempfile
import time
import zlib

# ---- Fixture files -------------------------------------------------------------------------------


def png_bytes(w, h, seed):
    """An RGB PNG of w x h, a gradient that depends on seed (stdlib only)."""
    rows = b"".join(
        b"\0" + bytes((x * 16 + seed * 40) % 256 if c == 0 else (y * 20 + c * 50) % 256
                      for x in range(w) for c in range(3))
        for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(
            ">I", zlib.crc32(kind + data) & 0xffffffff)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


TINY_OBJ = b"""# a tetrahedron
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
"""

TRIANGLE_BIN = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
TINY_GLTF = b"""{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                "min": [0, 0, 0], "max": [1, 1, 0]}],
 "bufferViews": [{"buffer": 0, "byteLength": 36}],
 "buffers": [{"uri": "tri.bin", "byteLength": 36}]}
"""
CAMERA_PATH = b"""{"keys": [
  {"time": 0, "position": [0, 0, 6], "target": [0, 0, 0], "fov": 40},
  {"time": 2, "position": [4, 1, 4], "target": [0, 0.5, 0]}]}
"""
VISUAL_JSON = (b'{"pitch": 40, "slope": 5.5, "center": 0.1, "DPI": 300, "screenW": 32, '
               b'"screenH": 24, "flipImageX": 0, "flipImageY": 0, "invView": 1}')
CAMERA_MATRIX = b"1 0 0 0\n0 1 0 0\n0 0 1 6\n0 0 0 1\n"

# The inputs a case may read, by kind; every case folder starts with all of them.
INPUTS = {
    "model": ["tiny.obj", "tri.gltf"],
    "image": ["a.png", "b.png", "c.png", "d.png"],
    "sky": ["sky.png"],
    "path": ["path.json"],
    "calibration": ["visual.json"],
    "matrix": ["camera.txt"],
}


def make_template(root, mvr, shared):
    """The files every case folder starts with (copied per case). Returns the shared models."""
    os.makedirs(root)
    files = {
        "tiny.obj": TINY_OBJ, "tri.gltf": TINY_GLTF, "tri.bin": TRIANGLE_BIN,
        "path.json": CAMERA_PATH, "visual.json": VISUAL_JSON, "camera.txt": CAMERA_MATRIX,
        "sky.png": png_bytes(32, 16, 5),
    }
    for i, name in enumerate(INPUTS["image"]):
        files[name] = png_bytes(16, 12, i)
    for name, data in files.items():
        with open(os.path.join(root, name), "wb") as f:
            f.write(data)
    # A stereo pair as .jps and .mpo, written by mvr itself (compose reads them back).
    for out in ("pair.jps", "pair.mpo"):
        r = subprocess.run([mvr, "compose", "a.png", "b.png", "-q", "-o", out], cwd=root,
                           capture_output=True, text=True, timeout=60)
        if r.returncode != 0:
            raise RuntimeError(f"set-up: mvr compose a.png b.png -o {out}: {r.stderr.strip()}")
    INPUTS["image"] += ["pair.jps", "pair.mpo"]
    models = []
    for name in ("suzanne.obj", "spot.obj"):  # small ones only: the fuzz runs in seconds
        path = os.path.join(shared, "models", name) if shared else ""
        if path and os.path.isfile(path):
            models.append(path)
    return models


# ---- Option catalogue ----------------------------------------------------------------------------
# type: the value's kind (picks the nonsense pool); valid: values a base command may use (all
# cheap at 16x12). "flag": no value.

FORMATS = ["anaglyph-dubois", "anaglyph-color", "anaglyph-half-color", "anaglyph-gray",
           "anaglyph-true", "anaglyph-dubois-gm", "anaglyph-dubois-ab", "sbs", "sbs-half", "tb",
           "tb-half", "rows", "columns", "checkerboard", "hdmi-frame-packing", "quilt",
           "lenticular", "jps", "mpo"]
DISPLAYS = ["lkg-8.9", "lkg-16", "portrait", "go", "lkg-16-spatial-portrait",
            "lkg-16-spatial-landscape", "lkg-32", "lkg-65", "3dtv", "sbs-half", "headset",
            "barrier"]

COMPOSE_OPTS = {
    "--format": ("enum", FORMATS),
    "--swap-eyes": ("flag", None),
    "--cross-eyed": ("flag", None),
    "--quilt": ("grid", ["2x1", "2x2", "1x2"]),
    "--jpeg-quality": ("int", ["1", "50", "100"]),
    "--base-viewpoint": ("int", ["1", "2"]),
    "--lenticular-calibration": ("calibration", ["visual.json"]),
    "--lenticular-pitch": ("float", ["40", "50.5"]),
    "--lenticular-slope": ("float", ["5.5", "-0.2"]),
    "--lenticular-center": ("float", ["0.1", "0"]),
    "--lenticular-dpi": ("float", ["300"]),
    "--lenticular-screen": ("grid", ["32x24", "16x12"]),
    "--lenticular-bgr": ("flag", None),
    "--lenticular-invert-views": ("flag", None),
    "--lenticular-flip-x": ("flag", None),
    "--lenticular-flip-y": ("flag", None),
}
MPO_OPTS = {"--baseline": ("float", ["0.065", "0"]), "--convergence": ("float", ["2", "0"])}

RENDER_OPTS = {
    "--views": ("int", ["1", "2", "2", "3", "4"]),
    "--view-grid": ("grid", ["2x2", "2x1", "3x1"]),
    "--rig": ("enum", ["offaxis", "toein", "parallel"]),
    "--interaxial": ("float", ["0.1", "0.02"]),
    "--separation": ("float_auto", ["0.02", "auto"]),
    "--convergence": ("float_auto", ["3", "auto"]),
    "--view-cone": ("float", ["30", "40"]),
    "--fov": ("float", ["30", "60"]),
    "--azimuth": ("float", ["30", "-45"]),
    "--elevation": ("float", ["10", "-20"]),
    "--distance": ("float_auto", ["5", "auto"]),
    "--target": ("vec3", ["0,0,0", "0.1,0.2,0"]),
    "--camera-position": ("vec3", ["0,0,5", "1,1,4"]),
    "--look-at": ("vec3", ["0,0,0"]),
    "--up": ("vec3", ["0,1,0"]),
    "--camera-matrix": ("matrix", ["camera.txt", "1,0,0,0,0,1,0,0,0,0,1,6,0,0,0,1"]),
    "--focal-length-mm": ("float", ["35", "50"]),
    "--sensor-width-mm": ("float", ["36", "24"]),
    "--background": ("colour", ["0.1,0.2,0.3", "#112233", "transparent"]),
    "--exposure": ("float_auto", ["1", "-1", "auto"]),
    "--shading": ("enum", ["flat", "vertex", "pixel"]),
    "--cull": ("flag", None),
    "--wireframe": ("flag", None),
    "--shadows": ("flag", None),
    "--shadow-map-size": ("int", ["64", "16"]),
    "--billboards": ("int", ["10", "0"]),
    "--billboard-size": ("float", ["0.1", "0"]),
    "--no-file-camera": ("flag", None),
    "--strict": ("flag", None),
    "--screen-width": ("float", ["50", "120"]),
    "--viewing-distance": ("float", ["60", "300"]),
    "--display": ("enum", DISPLAYS),
    "--backend": ("enum", ["soft", "soft", "soft", "gl"]),
    "--method": ("enum", ["unified", "multipass"]),
    "--depth": ("flag", None),
    "--depth-format": ("enum", ["png16", "exr"]),
    "--png-compression": ("enum", ["fast", "default", "small"]),
    "--write-cameras": ("flag", None),
    "--write": ("enum", ["views", "views,depth", "composites", "cameras", "views,composites",
                         "views,video"]),
    "-q": ("flag", None),
    "--check": ("flag", None),
    "--report-json": ("path_out", ["r.json", "out/r.json"]),
    "--sky": ("sky", ["gradient", "sky.png"]),
    "--floating-window": ("flag", None),
    "--letterbox": ("float", ["5", "10"]),
    "--label": ("label", ["hi@0.5,0.5", "far@0.2,0.8,10"]),
    "--label-anchor": ("anchor", ["a@0,0,0", "b@0.5,0.5,0"]),
}
RENDER_OPTS.update({k: v for k, v in COMPOSE_OPTS.items()})
SEQUENCE_OPTS = {
    "--frames": ("int", ["2", "1"]),
    "--orbit": ("float", ["30", "90"]),
    "--camera-path": ("path", ["path.json"]),
    "--frame-range": ("range", ["0:1", "1:", ":1"]),
    "--shard": ("shard", ["0/2", "1/2"]),
    "--fps": ("float", ["24", "2"]),
    "--threads": ("int", ["1", "2"]),
    "--video": ("path_out", ["v.mkv", "out/v.mkv", "out/v.mp4"]),
    "--codec": ("enum", ["h264", "ffv1"]),
    "--crf": ("int", ["20", "30"]),
    "--encoder-preset": ("enum", ["ultrafast", "fast"]),
    "--gather-stats": ("flag", None),
}
ALL_RENDER_OPTS = dict(RENDER_OPTS, **SEQUENCE_OPTS)
FILE_TYPES = {"calibration", "sky", "path", "matrix", "model", "image"}

# Nonsense: values no option of the type accepts ("never"), and values that stress a parser or
# a bound but may be valid ("odd"). Long strings and unicode are in both lists' spirit.
LONG = "x" * 5000
NEVER = {
    "int": ["", "abc", "nan", "1e30", "-1e30", "2147483648", "-2147483649", "1.5", "1_0",
            "\uff11\uff12", "1 2", "9" * 400],
    "float": ["", "abc", "nan", "inf", "-inf", "1e400", "-nan", "1,2", "\U0001F600", "--",
              "9" * 400 + "e9"],
    "float_auto": ["", "Auto", "abc", "nan", "inf", "-inf", "auto,1"],
    "vec3": ["", "1,2", "1,2,3,4", "nan,0,0", "a,b,c", "inf,0,0", "1;2;3", ",,"],
    "grid": ["", "0x0", "2", "x", "-2x2", "2x-1", "1e30x1", "99999x99999", "axb", "2x2x2"],
    "size": ["", "0x0", "16", "x12", "-16x12", "16x-12", "1e30x1", "99999x99999", "16x12.5",
             "abcxdef", "\uff11\uff16x12"],
    "enum": ["", "abc", "\u00e9", LONG, "SOFT", " soft"],
    "colour": ["", "#12345", "#GGGGGG", "1,2", "nan,0,0", "2,2,2", "-1,0,0", "red"],
    "range": ["", "a:b", "5:2", "-1:", "0:0", "::", "1e30:"],
    "shard": ["", "2/2", "-1/2", "0/0", "1", "a/b", "0/-1"],
    "label": ["", "noat", "a@nan,0", "a@1,2,3,4,5", "@", "a@,"],
    "anchor": ["", "noat", "a@nan,0,0", "a@1,2", "@"],
}
ODD = {
    "int": ["0", "-1", "2147483647", "-0", "+3", "0x10"],
    "float": ["0", "-1", "1e30", "-1e30", "1e-30", "-0", "4.9e-324", "1.7976931348623157e308"],
    "float_auto": ["0", "-1", "1e30", "1e-30"],
    "vec3": ["0,0,0", "1e30,0,0", "-1e30,1e30,0", "1e-30,0,0"],
    "grid": ["1x1", "128x1", "1x129"],
    "size": ["1x1", "2x1", "9000x1", "1x9000", "16X12"],
    "enum": [],
    "colour": ["0,0,0", "1,1,1", "#000000"],
    "range": ["5:9", "0:100"],
    "shard": ["0/1", "5/9"],
    "label": ["a@2,2", "a@-1,0.5", "\U0001F600@0.5,0.5", LONG + "@0.5,0.5", "a@0.5,0.5,-1",
              "a@0.5,0.5,1e30", "a\nb@0.5,0.5"],
    "anchor": ["a@1e30,0,0", "a@1e9,0,0"],
}
UNKNOWN_OPTIONS = ["--frobnicate", "--views=", "-x", "---views", "--size=16x12x1"]

# ---- Cases ---------------------------------------------------------------------------------------


class Case:
    """One command: argv after `mvr`, the files set up before it, what was done to it."""

    def __init__(self, index, seed):
        self.index = index
        self.rng = random.Random(f"{seed}:{index}")
        self.command = ""  # render | compose
        self.positional = []  # [(kind, value)]
        self.items = []  # [[option, value or None]]
        self.setup = []  # [(action, path, arg)]
        self.notes = []  # mutations, in words
        self.faults = set()  # usage / input / output: the classes of the mutations
        self.never = []  # (option, value) pairs that are never valid
        self.models = []
        self.single = False  # one mutation: the exit-code oracle knows its fault

    def argv(self):
        out = [self.command]
        for kind, value in self.positional:
            out.append(value)
        for opt, value in self.items:
            out.append(opt)
            if value is not None:
                out.append(value)
        return out

    def opts(self):
        return ALL_RENDER_OPTS if self.command == "render" else dict(COMPOSE_OPTS, **MPO_OPTS)

    def has(self, opt):
        return any(o == opt for o, _ in self.items)

    def add(self, opt, value=None):
        self.items.append([opt, value])


def valid_value(rng, opt, table):
    kind, values = table[opt]
    return None if kind == "flag" else rng.choice(values)


def base_case(case, models):
    rng = case.rng
    case.models = models
    pick = rng.random()
    if pick < 0.3:
        case.command = "compose"
        inputs = rng.choice([["a.png", "b.png"], ["pair.jps"], ["pair.mpo"],
                             ["a.png", "b.png", "c.png", "d.png"], ["a.png", "b.png", "c.png"]])
        case.positional = [("image", p) for p in inputs]
        n = 2 if inputs[0].startswith("pair") else len(inputs)
        fmts = [f for f in FORMATS if n == 2 or f in ("rows", "columns", "quilt", "lenticular",
                                                      "mpo")]
        fmt = rng.choice(fmts)
        out = rng.choice(["out", "out.png", "out.png", "out.jpg"])
        if fmt in ("jps", "mpo") and rng.random() < 0.5:
            out = "out." + fmt
        case.add("--format", fmt)
        case.add("-o", out)
        if fmt == "quilt":
            case.add("--quilt", "2x1" if n == 2 else ("2x2" if n == 4 else "3x1"))
        if fmt == "lenticular" and rng.random() < 0.5:
            case.add("--lenticular-calibration", "visual.json")
        extras = list(COMPOSE_OPTS) + (list(MPO_OPTS) if fmt == "mpo" else [])
        for _ in range(rng.choice([0, 0, 1, 2])):
            opt = rng.choice(extras)
            if opt not in ("--format", "--lenticular-calibration"):
                case.add(opt, valid_value(rng, opt, case.opts()))
        return
    case.command = "render"
    if rng.random() < 0.4:
        case.positional.append(("model", rng.choice(INPUTS["model"] + models)))
    elif rng.random() < 0.3:
        case.add("--scene", rng.choice(["default", "village", "textured"]))
    views = rng.choice(["1", "2", "2", "2", "3", "4"])
    case.add("--size", rng.choice(["16x12", "16x12", "12x16", "32x24"]))
    if rng.random() < 0.15:
        case.add("--display", rng.choice(DISPLAYS))
    else:
        case.add("--views", views)
    case.add("-o", "out")
    if rng.random() < 0.6:
        case.add("-q")
    if rng.random() < 0.3:
        case.add("--frames", rng.choice(["1", "2"]))
        if rng.random() < 0.5:
            case.add("--orbit", "30")
        elif rng.random() < 0.3:
            case.add("--camera-path", "path.json")
        if rng.random() < 0.3:
            case.add("--video", rng.choice(SEQUENCE_OPTS["--video"][1]))
            case.add("--codec", rng.choice(["h264", "ffv1"]))
            if case.items[-2][1].endswith(".mp4"):
                case.items[-1][1] = "h264"
    for _ in range(rng.choice([0, 1, 1, 2, 3])):
        opt = rng.choice(list(RENDER_OPTS))
        if opt == "--format":
            fmt = rng.choice(FORMATS if views == "2" else ["rows", "columns", "quilt"])
            case.add(opt, fmt)
            if fmt == "quilt" and not case.has("--quilt"):
                case.add("--quilt", f"{views}x1")
        elif opt not in ("--display", "--views", "--view-grid", "--scene", "--check"):
            case.add(opt, valid_value(rng, opt, RENDER_OPTS))


# Bad input files: (name, what it does to the path); each has its expected exit 2.
def bad_input(case, path):
    rng = case.rng
    kind = rng.choice(["missing", "empty", "truncated", "directory", "fifo", "dev-zero",
                       "garbage", "swapped-ext", "dev-null", "dangling-link"])
    ext = os.path.splitext(path)[1] or ".bin"
    name = f"bad-{kind}{ext}"
    if kind == "truncated" and os.path.exists(os.path.join(TEMPLATE, path)):
        size = os.path.getsize(os.path.join(TEMPLATE, path))
        case.setup.append(("truncate-copy", name, (path, rng.randrange(1, max(2, size)))))
    elif kind in ("empty", "truncated"):
        case.setup.append(("file", name, b""))
    elif kind == "directory":
        case.setup.append(("dir", name, None))
    elif kind == "fifo":
        case.setup.append(("fifo", name, None))
    elif kind == "dev-zero":
        case.setup.append(("symlink", name, "/dev/zero"))
    elif kind == "dev-null":
        case.setup.append(("symlink", name, "/dev/null"))
    elif kind == "dangling-link":
        case.setup.append(("symlink", name, "nowhere/at-all"))
    elif kind == "garbage":
        case.setup.append(("file", name, bytes(rng.randrange(256) for _ in range(200))))
    elif kind == "swapped-ext":
        other = "a.png" if ext != ".png" else "tiny.obj"
        case.setup.append(("truncate-copy", name, (other, 1 << 30)))
    case.notes.append(f"input {path} -> {name} ({kind})")
    case.faults.add("input")
    return name


def bad_output(case, opt, value):
    """A bad path for -o / --report-json / --video (or a trap inside a good one)."""
    rng = case.rng
    kind = rng.choice(["under-a-file", "file-as-dir", "dir-as-file", "dev-full", "empty",
                       "full-inside", "long-name"])
    is_dir = opt in ("-o", "--output") and os.path.splitext(value)[1] == ""
    if kind == "under-a-file":
        case.setup.append(("file", "blocker", b"a regular file\n"))
        new = "blocker/" + os.path.basename(value)
    elif kind == "file-as-dir" and is_dir:
        case.setup.append(("file", value, b"a regular file where a directory goes\n"))
        new = value
    elif kind in ("file-as-dir", "dir-as-file"):
        case.setup.append(("dir", value, None))
        case.setup.append(("file", value + "/keep.txt", b"kept\n"))
        new = value
    elif kind == "dev-full":
        name = "full" + os.path.splitext(value)[1]
        case.setup.append(("symlink", name, "/dev/full"))
        new = name if not is_dir else "/dev/full"
    elif kind == "empty":
        new = ""
    elif kind == "long-name":
        new = "n" * 300 + os.path.splitext(value)[1]
    else:  # full-inside: a later output is a /dev/full symlink (a disk full midway)
        if is_dir:
            target = rng.choice(["view-1.png", "view-0.png", "anaglyph.png", "depth-0.png",
                                 "frame-0001", "cameras.json"])
            case.setup.append(("dir", value, None))
            case.setup.append(("symlink", value + "/" + target, "/dev/full"))
        else:
            case.setup.append(("symlink", value, "/dev/full"))
        new = value
    case.notes.append(f"output {opt} {value!r} -> {new!r} ({kind})")
    case.faults.add("output")
    return new


def mutate(case):
    rng = case.rng
    table = case.opts()
    what = rng.choices(["drop", "dup", "swap", "nonsense", "odd", "add", "unknown", "input",
                        "output"], weights=[8, 6, 4, 22, 10, 10, 3, 16, 21])[0]
    items = case.items
    # --size never goes (a default 1024x768 or a display's 4096x4096 would cost seconds).
    movable = [i for i, (o, _) in enumerate(items) if o != "--size"]
    valued = [i for i, (o, v) in enumerate(items) if v is not None]
    if what == "drop" and movable:
        i = rng.choice(movable)
        case.notes.append(f"dropped {items[i][0]}")
        del items[i]
    elif what == "dup" and items:
        i = rng.choice(range(len(items)))
        opt = items[i][0]
        value = items[i][1]
        if value is not None and opt in table and rng.random() < 0.5:
            value = valid_value(rng, opt, table)
        case.notes.append(f"repeated {opt}")
        items.insert(rng.randrange(len(items) + 1), [opt, value])
    elif what == "swap" and len(valued) >= 2:
        i, j = rng.sample(valued, 2)
        items[i][1], items[j][1] = items[j][1], items[i][1]
        case.notes.append(f"swapped the values of {items[i][0]} and {items[j][0]}")
    elif what in ("nonsense", "odd") and valued:
        i = rng.choice(valued)
        opt = items[i][0]
        kind = "size" if opt == "--size" else table.get(opt, ("enum", None))[0]
        if opt in ("-o", "--output"):
            kind = "path_out"
        pool = (NEVER if what == "nonsense" else ODD).get(kind)
        if kind in FILE_TYPES or kind == "path_out" or not pool:
            pool = ["", LONG, "\u00e9\U0001F600", "-", "a b", "-o"]
        value = rng.choice(pool)
        items[i][1] = value
        case.notes.append(f"{opt} {value[:40]!r}{'...' if len(value) > 40 else ''} ({what})")
        if what == "nonsense" and kind in NEVER:
            case.faults.add("usage")
            case.never.append((opt, value))
    elif what == "add":
        opt = rng.choice(list(table))
        if opt == "--size":
            return
        kind = table[opt][0]
        r = rng.random()
        if kind == "flag":
            value = None
        elif r < 0.5 or kind not in NEVER:
            value = valid_value(rng, opt, table)
        else:
            value = rng.choice(NEVER[kind])
            case.faults.add("usage")
            case.never.append((opt, value))
        case.add(opt, value)
        case.notes.append(f"added {opt}" + ("" if value is None else f" {value[:40]!r}"))
    elif what == "unknown":
        opt = rng.choice(UNKNOWN_OPTIONS)
        items.insert(rng.randrange(len(items) + 1), [opt, None])
        case.notes.append(f"unknown option {opt!r}")
        case.faults.add("usage")
    elif what == "input":
        inputs = [("pos", i) for i, (k, _) in enumerate(case.positional) if k in FILE_TYPES]
        inputs += [("opt", i) for i, (o, v) in enumerate(items)
                   if o in table and table[o][0] in FILE_TYPES and v in sum(INPUTS.values(), [])]
        if not inputs:
            if case.command != "render":
                return
            case.positional.append(("model", "tiny.obj"))
            inputs = [("pos", len(case.positional) - 1)]
        where, i = rng.choice(inputs)
        if where == "pos":
            case.positional[i] = (case.positional[i][0], bad_input(case, case.positional[i][1]))
        else:
            items[i][1] = bad_input(case, items[i][1])
    elif what == "output":
        outs = [i for i, (o, v) in enumerate(items)
                if o in ("-o", "--output", "--report-json", "--video") and v]
        if case.command == "render" and rng.random() < 0.3:
            opt = rng.choice(["--report-json", "--video"])
            if opt == "--video" and not case.has("--frames"):
                case.add("--frames", "2")
            case.add(opt, "r.json" if opt == "--report-json" else "v.mkv")
            outs = [len(items) - 1]
        if not outs:
            return
        i = rng.choice(outs)
        items[i][1] = bad_output(case, items[i][0], items[i][1])


def make_case(index, seed, models):
    case = Case(index, seed)
    base_case(case, models)
    rng = case.rng
    if rng.random() < 0.08:
        case.notes.append("unmutated")
    else:
        count = rng.choice([1, 1, 1, 2, 2, 3])
        for _ in range(count):
            mutate(case)
        case.single = count == 1
    # Outputs that exist before the run: a failed run must leave them as they were.
    if rng.random() < 0.4:
        for opt, value in case.items:
            if opt in ("-o", "--output") and value and not any(p == value for _, p, _ in
                                                                 case.setup):
                if os.path.splitext(value)[1]:
                    case.setup.append(("file", value, b"old output\n"))
                else:
                    case.setup.append(("dir", value, None))
                    case.setup.append(("file", value + "/view-0.png", b"old view\n"))
                    case.setup.append(("file", value + "/keep.txt", b"kept\n"))
                case.notes.append(f"{value} existed before")
    return case


# ---- Running and checking ------------------------------------------------------------------------


def apply_setup(case, root):
    for action, path, arg in case.setup:
        full = os.path.join(root, path)
        parent = os.path.dirname(full)
        try:
            if parent and not os.path.isdir(parent):
                os.makedirs(parent)
            if os.path.lexists(full) and action != "file":
                continue
            if action == "file":
                if os.path.isdir(full) and not os.path.islink(full):
                    continue
                with open(full, "wb") as f:
                    f.write(arg)
            elif action == "dir":
                os.makedirs(full, exist_ok=True)
            elif action == "fifo":
                os.mkfifo(full)
            elif action == "symlink":
                os.symlink(arg, full)
            elif action == "truncate-copy":
                with open(os.path.join(root, arg[0]), "rb") as f:
                    data = f.read(arg[1])
                with open(full, "wb") as f:
                    f.write(data)
        except OSError:
            pass  # a set-up step that clashes with an earlier one: the case goes on without it


def snapshot(root):
    """{relative path: (type, size, hash | link target)} for everything under root."""
    out = {}

    def walk(d, rel):
        try:
            entries = sorted(os.scandir(d), key=lambda e: e.name)
        except OSError:
            return
        for e in entries:
            r = os.path.join(rel, e.name) if rel else e.name
            st = os.lstat(e.path)
            if stat.S_ISLNK(st.st_mode):
                out[r] = ("link", 0, os.readlink(e.path))
            elif stat.S_ISDIR(st.st_mode):
                out[r] = ("dir", 0, "")
                walk(e.path, r)
            elif stat.S_ISREG(st.st_mode):
                with open(e.path, "rb") as f:
                    out[r] = ("file", st.st_size, hashlib.sha1(f.read()).hexdigest()[:12])
            else:
                out[r] = ("special", 0, stat.S_IFMT(st.st_mode))

    walk(root, "")
    return out


def diff(before, after):
    lines = []
    for p in sorted(set(before) | set(after)):
        b, a = before.get(p), after.get(p)
        if b == a:
            continue
        if b is None:
            lines.append(f"+ {p} ({a[0]}{', %d bytes' % a[1] if a[0] == 'file' else ''})")
        elif a is None:
            lines.append(f"- {p} (was {b[0]})")
        else:
            lines.append(f"~ {p} ({b[0]} {b[1]} bytes -> {a[0]} {a[1]} bytes)")
    return lines


def normalise(message):
    """An error message with its particulars masked: the key of a failure kind."""
    m = re.sub(r"(--[a-z-]+)[ =][^:]*:", r"\1 …:", message)
    m = re.sub(r"Value .* not in range", "Value … not in range", m)
    m = re.sub(r"'[^']*'|\"[^\"]*\"|`[^`]*`", "'…'", m)
    m = re.sub(r"[-+]?\d[\d.e+-]*", "N", m)
    m = re.sub(r"\S*(bad-|blocker|full|out|n{20,})\S*", "PATH", m)
    return m[:110]


class Result:
    def __init__(self, case):
        self.case = case
        self.failures = []  # [(check, detail)]
        self.code = None
        self.stderr = ""
        self.changes = []
        self.seconds = 0.0
        self.folder = ""


def run_case(case, mvr, workdir, timeout, oracles, keep):
    res = Result(case)
    root = os.path.join(workdir, f"case-{case.index:04d}")
    tmp = root + ".tmp"
    shutil.copytree(TEMPLATE, root, symlinks=True)
    os.makedirs(tmp)
    apply_setup(case, root)
    before = snapshot(root)
    env = dict(os.environ, TMPDIR=tmp, LC_ALL="C.UTF-8")
    env.pop("MVR_PROGRESS_AFTER_MS", None)
    start = time.monotonic()
    proc = subprocess.Popen([mvr] + case.argv(), cwd=root, env=env, stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            start_new_session=True)
    try:
        _, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        _, err = proc.communicate()
        res.failures.append(("hang", f"no exit in {timeout} s"))
    res.seconds = time.monotonic() - start
    res.code = proc.returncode
    res.stderr = err.decode("utf-8", "replace")
    res.folder = root
    lines = res.stderr.splitlines()
    hung = bool(res.failures)
    code = res.code
    argv_text = " ".join(case.argv())
    if hung:
        pass
    elif code < 0 or code >= 128:
        sig = -code if code < 0 else code - 128
        try:
            name = signal.Signals(sig).name
        except ValueError:
            name = str(sig)
        res.failures.append(("signal", f"killed by {name}"))
    elif code > 5:
        res.failures.append(("bad-exit-code", f"exit {code}"))
    if not hung and code == 0:
        other = [ln for ln in lines if not SUCCESS_LINE.match(ln)]
        if other:
            res.failures.append(("stderr-on-success", other[0][:200]))
    elif not hung and 0 < code <= 5:
        noise = 0
        while noise < len(lines) and SUCCESS_LINE.match(lines[noise]):
            noise += 1
        rest = lines[noise:]
        ok = (len(rest) >= 1 and rest[0].startswith("error: ") and len(rest) <= 2 and
              (len(rest) == 1 or rest[1].startswith("run `mvr")))
        if not ok:
            res.failures.append(("error-format", f"{len(lines)} line(s): " +
                                 " | ".join(ln[:100] for ln in lines[:3])))
        elif noise:
            res.failures.append(("noise-before-error", f"{noise} line(s) before the error: " +
                                 lines[0][:100]))
        for digits in re.findall(r"\d{40,}", res.stderr):
            if digits not in argv_text:
                res.failures.append(("unreadable-number", f"a {len(digits)}-digit number"))
                break
    if not hung and code != 0:
        res.changes = diff(before, snapshot(root))
        if res.changes:
            res.failures.append(("files-changed", f"{len(res.changes)} change(s)"))
    if not hung:
        left = os.listdir(tmp)
        if left:
            res.failures.append(("temp-left", "in TMPDIR: " + ", ".join(sorted(left)[:5])))
        if code == 0:
            temps = [p for p in diff(before, snapshot(root))
                     if re.search(r"\.(part|tmp)\b|~ \(", p) and p.startswith("+")]
            if temps:
                res.failures.append(("temp-left", "after a success: " + temps[0]))
    if oracles and not hung:
        never = [p for p in case.never if list(p) in case.items]  # not dropped since
        if code == 0 and never:
            opt, value = never[0]
            res.failures.append(("accepted-nonsense", f"{opt} {value[:40]!r} accepted"))
        expect = {"usage": 1, "input": 2, "output": 4}
        if 0 < code <= 5 and len(case.faults) == 1 and case.single:
            want = expect[next(iter(case.faults))]
            if code != want:
                res.failures.append(("exit-code", f"exit {code} for a fault of class "
                                     f"{next(iter(case.faults))} (expected {want})"))
    if not keep and not res.failures:
        shutil.rmtree(root, ignore_errors=True)
        shutil.rmtree(tmp, ignore_errors=True)
    return res


def kind_key(res, check):
    c = res.case
    lines = res.stderr.splitlines()
    errors = [ln for ln in lines if ln.startswith("error: ")]
    first = (errors or lines or [""])[0]
    if check == "noise-before-error":
        return f"{check}: {c.command}: {lines[0].split(' ')[0]} lines before the error"
    if check in ("files-changed", "error-format", "unreadable-number", "exit-code"):
        return f"{check}: {c.command}: {normalise(first)}"
    if check == "accepted-nonsense":
        return f"{check}: {c.command} {next(d for k, d in res.failures if k == check).split(' ')[0]}"
    if check == "stderr-on-success":
        return f"{check}: {c.command}: {normalise(first)}"
    return f"{check}: {c.command}: {'; '.join(re.sub(r'[(].*', '', n) for n in c.notes)[:80]}"


def report(res, check, detail, seed, argv0, mvr):
    c = res.case
    out = [f"FAIL case {c.index} [{check}] {detail}",
           f"  mutations: {'; '.join(c.notes)}"]
    if c.setup:
        out.append("  set up: " + "; ".join(
            f"{p} {a}" + (f" -> {x}" if a == "symlink" else "") for a, p, x in c.setup))
    out.append(f"  cd {res.folder} && {shlex.quote(mvr)} " +
               " ".join(shlex.quote(a) for a in c.argv())[:600])
    out.append(f"  exit {res.code} after {res.seconds:.1f} s; stderr:")
    out += ["    " + ln[:300] for ln in res.stderr.splitlines()[:6]] or ["    (nothing)"]
    if res.changes:
        out.append("  files changed:")
        out += ["    " + ln for ln in res.changes[:12]]
    out.append(f"  rerun: {argv0} {mvr} --seed {seed} --only {c.index} --keep")
    return "\n".join(out)


TEMPLATE = ""
# What a successful run may print on stderr: warnings, notes, a sequence's progress.
SUCCESS_LINE = re.compile(r"(warning: |note: |frame \d+ done \(|\r?\[[# .]*\] )")


def main():
    global TEMPLATE
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mvr")
    ap.add_argument("--seed", type=int, default=44)
    ap.add_argument("--cases", type=int, default=300)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--timeout", type=float, default=10.0)
    ap.add_argument("--only", default="", help="comma list of case numbers")
    ap.add_argument("--keep", action="store_true", help="keep every case's folder")
    ap.add_argument("--oracles", action="store_true",
                    help="also fail on exit codes and accepted nonsense (heuristics)")
    ap.add_argument("-v", "--verbose", action="store_true", help="print every case")
    args = ap.parse_args()
    mvr = os.path.abspath(args.mvr)
    if not os.access(mvr, os.X_OK):
        print(f"cli_fuzz: {mvr} is not an executable", file=sys.stderr)
        return 2
    shared = os.environ.get("MVR_SHARED_DIR") or os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared")
    workdir = tempfile.mkdtemp(prefix="mvr-cli-fuzz-")
    TEMPLATE = os.path.join(workdir, "template")
    try:
        models = make_template(TEMPLATE, mvr, shared)
    except (RuntimeError, OSError, subprocess.SubprocessError) as e:
        print(f"cli_fuzz: {e}", file=sys.stderr)
        return 2
    indices = ([int(i) for i in args.only.split(",")] if args.only else range(args.cases))
    cases = [make_case(i, args.seed, models) for i in indices]
    start = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = list(pool.map(
            lambda c: run_case(c, mvr, workdir, args.timeout, args.oracles,
                               args.keep or bool(args.only)), cases))
    elapsed = time.monotonic() - start
    kinds = {}
    codes = {}
    argv0 = os.path.abspath(__file__)
    for res in results:
        codes[res.code] = codes.get(res.code, 0) + 1
        if args.verbose:
            print(f"case {res.case.index}: exit {res.code} {res.seconds:.2f} s: "
                  f"{' '.join(res.case.argv())[:160]}")
        for check, detail in res.failures:
            print(report(res, check, detail, args.seed, argv0, mvr), flush=True)
            kinds.setdefault(kind_key(res, check), []).append(res.case.index)
    slowest = max(results, key=lambda r: r.seconds)
    print(f"cli_fuzz: {len(results)} cases (seed {args.seed}) in {elapsed:.1f} s, "
          f"{args.jobs} jobs; exit codes {dict(sorted(codes.items(), key=str))}; slowest case "
          f"{slowest.case.index} {slowest.seconds:.1f} s")
    if not args.keep and not args.only and not kinds:
        shutil.rmtree(workdir, ignore_errors=True)
    if not kinds:
        print("cli_fuzz: every case kept the contract")
        return 0
    print(f"cli_fuzz: {sum(len(v) for v in kinds.values())} failures of {len(kinds)} kinds "
          f"(cases kept in {workdir}):")
    for key, idx in sorted(kinds.items()):
        print(f"  {len(idx):4d} x {key}   (e.g. case {idx[0]})")
    return 1


if __name__ == "__main__":
    sys.exit(main())
