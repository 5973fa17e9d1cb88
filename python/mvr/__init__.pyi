# Typed stub of the mvr package (python/mvr/__init__.py over the C++ module mvr._core).
import os
from typing import Any, Literal, Optional, Sequence, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, os.PathLike[str]]
_Pair = Union[str, tuple[int, int]]  # "WxH" / "CxR" or (w, h) / (c, r)
_Vec3 = Union[str, Sequence[float]]  # "x,y,z" or (x, y, z)
_Views = Union[npt.NDArray[np.uint8], Sequence[Union[npt.NDArray[np.uint8], _Path]]]

class ParameterError(TypeError, ValueError):
    """A keyword of the wrong type, or an unknown keyword."""

class Rig(TypedDict):
    kind: Literal["offaxis", "toein", "parallel"]
    columns: int
    rows: int
    views: int
    interaxial: float
    interaxial_y: float
    convergence: float
    separation: float
    fov: float
    aspect: float
    near: float
    far: float
    eyes: list[tuple[float, float, float]]
    view_cone: float
    notes: list[str]  # what convergence/separation "auto" chose, warnings

class Comfort(TypedDict, total=False):
    min_parallax: float
    max_parallax: float
    min_parallax_percent: float
    max_parallax_percent: float
    nearest_distance: float
    farthest_distance: float
    comfortable: bool
    why: str
    text: str
    screen: dict[str, Any]  # with screen_width=: the report against the screen (docs/displays.md)

class RenderResult:
    @property
    def color(self) -> npt.NDArray[np.uint8]: ...  # (N, H, W, 4)
    @property
    def depth(self) -> npt.NDArray[np.float32] | None: ...  # (N, H, W)
    @property
    def method(self) -> str: ...
    @property
    def note(self) -> str: ...
    @property
    def backend(self) -> str: ...
    @property
    def rig(self) -> Rig: ...
    @property
    def comfort(self) -> Comfort: ...
    @property
    def composites(self) -> dict[str, npt.NDArray[np.uint8] | bytes]: ...
    @property
    def scene(self) -> str: ...
    @property
    def triangles(self) -> int: ...
    @property
    def copied_views(self) -> int: ...  # images copied into color/depth (0: zero copy)
    @property
    def size(self) -> tuple[int, int]: ...
    @property
    def shading(self) -> str: ...
    @property
    def elapsed_ms(self) -> float: ...
    @property
    def written(self) -> list[str]: ...
    @property
    def frame(self) -> int | None: ...  # the frame of render_sequence(); None for render()
    @property
    def views(self) -> list[Any]: ...  # per view: world_from_camera, view_matrix, projection, intrinsics, near, far
    @property
    def distance(self) -> npt.NDArray[np.float32] | None: ...  # (N, H, W), inf where empty
    def __len__(self) -> int: ...

class Mesh:
    def __init__(
        self,
        vertices: npt.ArrayLike,
        faces: npt.ArrayLike,
        normals: npt.ArrayLike | None = None,
        uvs: npt.ArrayLike | None = None,
        colors: None = None,
        texture: npt.NDArray[np.uint8] | None = None,
        name: str = "mesh",
        placement: str | None = None,
    ) -> None: ...
    @property
    def name(self) -> str: ...
    @property
    def vertex_count(self) -> int: ...
    @property
    def triangle_count(self) -> int: ...

class RenderSequence:
    """What render_sequence() returns: one RenderResult per frame, rendered when asked for."""
    @property
    def frames(self) -> list[int]: ...
    def __iter__(self) -> RenderSequence: ...
    def __next__(self) -> RenderResult: ...
    def __len__(self) -> int: ...

def render(
    models: _Path | Mesh | Sequence[_Path | Mesh] | None = None,
    *,
    scene: Literal["default", "village", "textured"] = ...,
    grid: int = ...,
    views: int = ...,
    view_grid: _Pair = ...,
    rig: Literal["offaxis", "toein", "parallel"] = ...,
    interaxial: float = ...,
    separation: float | Literal["auto"] = ...,
    depth_percent: float = ...,
    view_cone: float = ...,
    convergence: float | Literal["auto"] = ...,
    display: str = ...,
    screen_width: float = ...,
    viewing_distance: float = ...,
    report_json: _Path = ...,
    fov: float = ...,
    no_file_camera: bool = ...,
    exposure: float | Literal["auto"] = ...,
    tonemap: Literal["none", "khr-neutral", "aces", "auto"] = ...,
    environment: _Path = ...,
    size: _Pair = ...,
    shading: Literal["flat", "vertex", "pixel"] = ...,
    specular: Literal["center", "per-view"] = ...,
    cull: bool = ...,
    wireframe: bool = ...,
    shadows: bool = ...,
    shadow_map_size: int = ...,
    aa: Literal[1, 2, 4, 8] = ...,
    billboards: int = ...,
    billboard_size: float = ...,
    backend: str = ...,
    method: str = ...,
    depth: bool = ...,
    quiet: bool = ...,
    output: _Path = ...,
    format: str | Sequence[str] = ...,
    swap_eyes: bool = ...,
    cross_eyed: bool = ...,
    quilt: _Pair = ...,
    jpeg_quality: int = ...,
    base_viewpoint: int = ...,
    lenticular_calibration: _Path = ...,
    sky: _Path = ...,
    floating_window: bool = ...,
    letterbox: float = ...,
    label: str | Sequence[str] = ...,
    label_anchor: str | Sequence[str] = ...,
    angular_aa: float | Literal["auto", "off"] = ...,
    synthesize: int = ...,
    direct: bool = ...,
    azimuth: float = ...,
    elevation: float = ...,
    distance: float | Literal["auto"] = ...,
    target: _Vec3 = ...,
    camera_position: _Vec3 = ...,
    look_at: _Vec3 = ...,
    up: _Vec3 = ...,
    camera_matrix: Sequence[float] | Sequence[Sequence[float]] | _Path = ...,
    focal_length_mm: float = ...,
    sensor_width_mm: float = ...,
    background: _Vec3 | str = ...,
    screen_mm: _Pair | str = ...,
    screen_corners: Sequence[float] | Sequence[Sequence[float]] | str = ...,
    screen_tilt: float = ...,
    head: _Vec3 = ...,
    ipd_mm: float = ...,
    eye_track: _Path = ...,
    look_around: float = ...,
    depthiness: float = ...,
    focus: float = ...,
    rgbd_depth_position: Literal["right", "left", "top", "bottom"] = ...,
    depth_factor: float = ...,
    depth_format: Literal["png16", "exr"] = ...,
    png_compression: Literal["fast", "default", "small"] = ...,
    view_range: _Pair | str = ...,
    write: str | Sequence[str] = ...,
    write_cameras: bool = ...,
    strict: bool = ...,
    lenticular_pitch: float = ...,
    lenticular_slope: float = ...,
    lenticular_center: float = ...,
    lenticular_dpi: float = ...,
    lenticular_screen: _Pair = ...,
    lenticular_bgr: bool = ...,
    lenticular_invert_views: bool = ...,
    lenticular_flip_x: bool = ...,
    lenticular_flip_y: bool = ...,
    **options: Any,
) -> RenderResult: ...
def render_sequence(
    models: _Path | Sequence[_Path] | None = None,
    *,
    frames: int = ...,
    orbit: float = ...,
    camera_path: _Path = ...,
    fps: float = ...,
    frame_range: str = ...,
    shard: str = ...,
    **options: Any,  # every keyword of render()
) -> RenderSequence: ...
def compose(
    format: str,
    views: _Views,
    *,
    output: _Path = ...,
    quiet: bool = ...,
    swap_eyes: bool = ...,
    cross_eyed: bool = ...,
    quilt: _Pair = ...,
    jpeg_quality: int = ...,
    base_viewpoint: int = ...,
    baseline: float = ...,
    convergence: float = ...,
    lenticular_calibration: _Path = ...,
    lenticular_pitch: float = ...,
    lenticular_slope: float = ...,
    lenticular_center: float = ...,
    lenticular_dpi: float = ...,
    lenticular_screen: _Pair = ...,
    lenticular_bgr: bool = ...,
    lenticular_invert_views: bool = ...,
    lenticular_flip_x: bool = ...,
    lenticular_flip_y: bool = ...,
    **options: Any,
) -> npt.NDArray[np.uint8] | bytes: ...
def from_rgbd(
    files: Union[_Path, Sequence[_Path]],
    display: str,
    depthiness: Optional[float] = ...,
    focus: Optional[float] = ...,
    rgbd_depth_position: Optional[Literal["right", "left", "top", "bottom"]] = ...,
) -> npt.NDArray[np.uint8]: ...
def load_mesh(path: _Path) -> dict[str, Any]: ...
def info() -> dict[str, Any]: ...
def write_png(path: _Path, array: npt.ArrayLike, png_compression: Literal["fast", "default", "small"] = ...) -> None: ...
