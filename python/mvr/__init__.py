"""mvr — multi-view (stereo, light-field) rendering from Python.

The C++ library behind the ``mvr`` command line, with the same images:

>>> import mvr
>>> r = mvr.render(views=2, size=(320, 240))      # the default scene, a stereo pair
>>> r.color.shape, r.color.dtype                   # (N, H, W, 4) RGBA, no copy
((2, 240, 320, 4), dtype('uint8'))
>>> quilt = mvr.compose("quilt", r.color)          # any ``mvr compose`` format

Keywords are the options of ``mvr render`` / ``mvr compose`` with dashes as underscores
(``view_grid=(3, 3)``, ``size=(1024, 768)``, ``cull=True``); a (w, h) pair stands for "WxH".

Errors: :class:`ValueError` for bad parameters (mvr's usage errors), :class:`FileNotFoundError`
or :class:`OSError` for files, :class:`RuntimeError` for what this machine or driver cannot do.
A keyword of the wrong type or an unknown keyword raises :class:`ParameterError`, which is both
a :class:`TypeError` and a :class:`ValueError`.
"""

from . import _core
from ._core import Mesh, ParameterError, RenderResult, RenderSequence

__all__ = ["render", "render_sequence", "compose", "from_rgbd", "load_mesh", "info", "write_png",
           "Mesh", "RenderResult", "RenderSequence", "ParameterError"]
__version__ = _core.info()["version"]


def render(models=None, **options):
    """Render a scene from N viewpoints, as ``mvr render MODELS... --OPTION VALUE...`` does.

    models: model files (OBJ, PLY, glTF 2.0; str or os.PathLike) and :class:`Mesh` objects (numpy
    arrays), one or a list (meshes after the files); none: the procedural default scene.

    options (every ``mvr render`` option, dashes as underscores): views (2), view_grid ((C, R)
    or "CxR"), rig ("offaxis" | "toein" | "parallel" | "screen"), interaxial, separation
    (a number or "auto"; depth_percent= 0 < P <= 100 the share of the screen's budget auto fills),
    convergence, rig="screen"'s screen_mm ((W, H) mm), screen_corners (three (X, Y, Z) mm),
    eyes (two (X, Y, Z) mm), head ((X, Y, Z) mm) and ipd_mm (an eye-tracked monitor's pair,
    docs/displays.md),
    fov (45), size ((W, H) or "WxH", default 1024x768), shading ("flat" | "vertex" | "pixel"),
    cull, wireframe, grid, backend ("soft", "gl", ...), method (default: the backend's fastest
    exact method), format (a format or a list: the composites land in ``.composites``) and the
    composite options (swap_eyes, cross_eyed, quilt, jpeg_quality, base_viewpoint,
    lenticular_*; format="rgbd" with depthiness, focus, rgbd_depth_position: the centre view's
    colour and depth, docs/displays.md). view_range=(A, B) renders only views A..B of the rig
    (``.color`` holds them in order; their files are named as in the whole render, view-A.png
    ...). output=DIR also writes the files ``mvr render -o DIR`` writes (view-N.png,
    depth-N.png with depth=True, anaglyph.png for a pair, the formats' files; ``.written``
    lists them); quiet is accepted (nothing is printed). The depth is always returned.
    direct=True with format="lenticular" (``mvr render --direct``, docs/displays.md): the panel
    composed from the views' rows as soft:unified finishes them, in
    ``.composites["lenticular"]``; no view is kept (``.color`` and ``.depth`` are None).

    Returns a :class:`RenderResult`: ``.color`` uint8 (N, H, W, 4), ``.depth`` float32
    (N, H, W) (window depth, 1 = nothing drawn), ``.method``, ``.rig`` (dict), ``.comfort``
    (dict: the parallax report ``mvr render`` prints), ``.composites``. The arrays own the C++
    buffers (their ``.base`` is the owning capsule); the GIL is released while rendering.
    """
    return _core.render(models, **options)


def render_sequence(models=None, **options):
    """Render a sequence, as ``mvr render --frames F / --orbit DEG / --camera-path FILE`` does.

    Takes the keywords of :func:`render` and the sequence's: frames, orbit (degrees about the
    scene centre over the frames), camera_path (a keyframe JSON file, docs/animation.md), fps
    (24), frame_range ("A:B"), shard ("I/N") and, with rig="screen", eye_track (a CSV of
    t,lx,ly,lz,rx,ry,rz: the eyes per frame, docs/displays.md); a model file's animation plays. Bad keywords
    raise here, before any frame is rendered.

    Returns an iterator of one :class:`RenderResult` per frame (``.frame`` is its number), each
    rendered when it is asked for. output=DIR writes DIR/frame-NNNN/ per frame, the files
    ``mvr render`` writes there (views, depth, anaglyph.png for a pair, the formats).
    """
    return _core.RenderSequence(models, **options)


def compose(format, views, **options):
    """Compose views into a stereo / multi-view format, as ``mvr compose -f FORMAT`` does.

    views: an (N, H, W, 4) uint8 array (e.g. ``render(...).color``), or a list whose items are
    (H, W, 4) / (H, W, 3) uint8 arrays or image files (PNG, JPEG; an MPO or .jps gives its
    views), leftmost first. options: every ``mvr compose`` option (swap_eyes, cross_eyed,
    quilt=(C, R), jpeg_quality, base_viewpoint, baseline, convergence, lenticular_calibration,
    lenticular_pitch, ...), and output: a file (.png .jpg .jpeg .jps .mpo) or a folder that also
    gets the composite, as ``mvr compose -o`` writes it.

    Returns a uint8 (H, W, 4) array, or bytes (the file) for ``mpo`` and ``jps``.
    """
    return _core.compose(format, views, **options)


def from_rgbd(files, display, depthiness=None, focus=None, rgbd_depth_position=None):
    """A light-field display's views from an RGB-D picture, as ``mvr compose --from-rgbd
    --display DISPLAY`` makes them (docs/displays.md, "RGB-D in, quilt out").

    files: one picture with colour and grey depth side by side (white = near; where the depth
    lies: rgbd_depth_position, else its FILE.json sidecar, else right), or a list of two files,
    colour then depth. mvr's own rgbd.json gives the depth in world units and the camera;
    other depth maps are taken as disparity. depthiness (0..2) scales every parallax, focus
    (-0.05..0.05) moves the focal plane toward the viewer.

    Returns the views as a uint8 (N, H, W, 4) array, leftmost first, of the display's view
    size: ``compose("quilt", views, quilt=(8, 6))`` makes the Portrait's quilt.
    """
    return _core.from_rgbd(files, display, depthiness, focus, rgbd_depth_position)


def load_mesh(path):
    """Load a model file (OBJ, PLY, glTF 2.0) as ``mvr render`` does.

    Returns a dict: positions float32 (V, 3), normals float32 (V, 3), texcoords float32 (V, 2)
    or (0, 2), indices uint32 (T, 3) (counter-clockwise = front), triangles, path.
    Missing file: FileNotFoundError; unreadable model: OSError.
    """
    return _core.load_mesh(path)


def info():
    """What ``mvr info`` says, as a dict: version, limits (max_views, max_view_size,
    max_framebuffer_bytes, max_lights), backends (name, description, gpu, available,
    default_method, info lines, methods: name / supported / reason) and formats."""
    return _core.info()


def write_png(path, array, png_compression="fast"):
    """Write an image as PNG: uint8 (H, W, 4), (H, W, 3) or (H, W) gray; a float (H, W) depth
    image is written as ``mvr render --depth`` does (16-bit gray, near = black).
    png_compression: "fast" (the default, as ``mvr render`` writes), "default" or "small": the
    same pixels in every mode. Errors: OSError when the file cannot be written."""
    _core.write_png(path, array, png_compression)
