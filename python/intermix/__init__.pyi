"""Type stubs for intermix (the extension module _intermix and the Image class)."""

import os
from typing import Any, Literal, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

PathLike = Union[str, os.PathLike[str]]
Space = Literal["LPS", "RAS"]
View = Literal["anterior", "posterior", "left", "right", "superior", "inferior"]
ColourBarPosition = Literal["top-right", "top-left", "bottom-right", "bottom-left", "outside"]
Colouring = Literal[
    "direction", "streamline_direction", "fixed", "point_value", "streamline_value", "group"
]
ArrayLike = npt.ArrayLike
# A scene document value: what JSON holds, numpy arrays and scalars, paths, Volume, Mesh and
# Streamlines.
SceneValue = Any

class Image(np.ndarray):
    """An (H, W, 4) float32 array of premultiplied linear RGBA, as renders return it."""

    def to_uint8(self, linear: bool = False) -> npt.NDArray[np.uint8]: ...
    def save(self, path: PathLike, linear: bool = False) -> None: ...
    def _repr_png_(self) -> Optional[bytes]: ...

class Volume:
    """Numpy voxels or a nibabel image with a 4x4 index-to-world affine; zero-copy for
    uint8/int16/uint16/float32."""

    def __init__(
        self,
        array: Any,
        affine: Optional[ArrayLike] = None,
        *,
        space: Optional[Space] = None,
        axes: Literal["auto", "kji", "ijk"] = "auto",
        frame: Optional[int] = None,
    ) -> None: ...
    @property
    def array(self) -> Any: ...
    @property
    def voxels(self) -> np.ndarray: ...
    @property
    def affine(self) -> npt.NDArray[np.float64]: ...
    @property
    def lps_affine(self) -> npt.NDArray[np.float64]: ...
    @property
    def shape(self) -> Tuple[int, int, int]: ...
    @property
    def dtype(self) -> np.dtype: ...
    @property
    def spacing(self) -> Tuple[float, float, float]: ...
    @property
    def range(self) -> Tuple[float, float]: ...
    @property
    def shares_memory(self) -> bool: ...
    @property
    def _data_address(self) -> int: ...

class Mesh:
    """A triangle mesh in LPS millimetres."""

    def __init__(
        self,
        vertices: ArrayLike,
        triangles: ArrayLike,
        normals: Optional[ArrayLike] = None,
        colors: Optional[ArrayLike] = None,
        *,
        space: Space = "LPS",
        crease_angle_deg: float = 60.0,
    ) -> None: ...
    @property
    def vertices(self) -> npt.NDArray[np.float32]: ...
    @property
    def triangles(self) -> npt.NDArray[np.uint32]: ...
    @property
    def normals(self) -> Optional[npt.NDArray[np.float32]]: ...
    @property
    def colors(self) -> Optional[npt.NDArray[np.float32]]: ...

class Streamlines:
    """A tractogram in LPS millimetres: from a file, a nibabel Tractogram or ArraySequence, a
    DIPY StatefulTractogram or list of (n, 3) arrays, or (N, 3) points with count + 1 offsets.
    Arrays are RAS unless space="LPS"; they are converted once into intermix's float32 points
    (read through the buffer protocol, no Python copy)."""

    def __init__(
        self,
        source: Any,
        offsets: Optional[ArrayLike] = None,
        *,
        space: Optional[Space] = None,
        point_values: Optional[Mapping[str, ArrayLike]] = None,
        streamline_values: Optional[Mapping[str, ArrayLike]] = None,
        values: Union[PathLike, Sequence[PathLike], None] = None,
    ) -> None: ...
    @staticmethod
    def load(
        path: PathLike, values: Union[PathLike, Sequence[PathLike], None] = None
    ) -> "Streamlines": ...
    @property
    def count(self) -> int: ...
    def __len__(self) -> int: ...
    def __getitem__(self, index: int) -> npt.NDArray[np.float32]: ...
    @property
    def points(self) -> npt.NDArray[np.float32]: ...
    @property
    def offsets(self) -> npt.NDArray[np.uint32]: ...
    @property
    def lengths(self) -> npt.NDArray[np.int64]: ...
    @property
    def point_values(self) -> dict[str, npt.NDArray[np.float32]]: ...
    @property
    def streamline_values(self) -> dict[str, npt.NDArray[np.float32]]: ...
    @property
    def value_names(self) -> list[str]: ...
    @property
    def groups(self) -> list[str]: ...
    @property
    def notes(self) -> list[str]: ...

class Scene:
    """A scene in the schema of intermix's JSON scene files."""

    def __init__(self, base_dir: Optional[PathLike] = None) -> None: ...
    @staticmethod
    def from_file(path: PathLike) -> "Scene": ...
    @staticmethod
    def from_dict(scene: Mapping[str, SceneValue], base_dir: Optional[PathLike] = None) -> "Scene": ...
    @staticmethod
    def from_json(text: str, base_dir: Optional[PathLike] = None) -> "Scene": ...
    @staticmethod
    def from_files(
        paths: Union[PathLike, Sequence[PathLike]], view: View = "anterior"
    ) -> "Scene": ...
    def set(self, path: Union[str, Mapping[str, SceneValue]], value: SceneValue = ...) -> None: ...
    def set_view(self, view: View) -> None: ...
    def add_volume(
        self,
        name: str,
        source: Any,
        affine: Optional[ArrayLike] = None,
        space: Optional[Space] = None,
        axes: Literal["auto", "kji", "ijk"] = "auto",
        frame: Optional[int] = None,
        **fields: SceneValue,
    ) -> None: ...
    def add_mesh(
        self, name: str, source: Union[Mesh, PathLike, Mapping[str, SceneValue]], **fields: SceneValue
    ) -> None: ...
    def add_streamlines(
        self,
        source: Union[Streamlines, PathLike, Mapping[str, SceneValue], Any],
        radius: float = 0.5,
        colouring: Optional[Colouring] = None,
        color: Optional[Sequence[float]] = None,
        value: Optional[str] = None,
        colormap: Optional[str] = None,
        opacity: float = 1.0,
        stride: int = 1,
        min_length: float = 0.0,
        name: Optional[str] = None,
        **fields: SceneValue,
    ) -> None: ...
    def add_plane(self, name: str, **fields: SceneValue) -> None: ...
    def to_dict(self) -> dict: ...
    def copy(self) -> "Scene": ...
    def __copy__(self) -> "Scene": ...
    @property
    def names(self) -> list[str]: ...
    @property
    def notes(self) -> list[str]: ...
    @property
    def measurements(self) -> list[dict[str, Any]]: ...
    @property
    def file(self) -> Optional[str]: ...
    @property
    def base_dir(self) -> str: ...
    @property
    def camera(self) -> dict[str, Any]: ...
    def render(
        self,
        method: Optional[str] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: Optional[int] = None,
        threads: Optional[int] = None,
        view: Optional[View] = None,
        colorbar: Union[bool, ColourBarPosition] = False,
        colorbar_scale: float = 1.0,
    ) -> Image: ...
    def figure(
        self,
        kind: Literal["ortho", "mosaic", "glass"] = "ortho",
        cut: Optional[Sequence[float]] = None,
        axis: Literal["axial", "coronal", "sagittal"] = "axial",
        cuts: Optional[Sequence[float]] = None,
        slices: int = 7,
        columns: int = 0,
        height: int = 256,
        colorbar: bool = True,
        annotate: bool = True,
        crosshair: bool = True,
        plot_abs: bool = True,
    ) -> Image: ...
    def show(self, width: int = 640, height: int = 480) -> View: ...
    def _repr_png_(self) -> bytes: ...

class View:
    """A scene shown by intermix's viewer in this process (Scene.show): in Jupyter, the page in
    the cell."""

    @property
    def url(self) -> str: ...
    @property
    def open(self) -> bool: ...
    def close(self) -> None: ...
    def _repr_html_(self) -> str: ...

class RendererStats:
    """What the last frame of a Renderer reused."""

    @property
    def stages(self) -> int: ...
    @property
    def stages_run(self) -> int: ...
    @property
    def stages_merged(self) -> int: ...
    @property
    def stream_bytes_per_pixel(self) -> float: ...
    @property
    def kept_bytes_per_pixel(self) -> float: ...
    @property
    def recast_unchanged(self) -> bool: ...

class Renderer:
    """Renders frame after frame, keeping per-object stages (zslab methods)."""

    def __init__(self, kept_budget: Optional[int] = None) -> None: ...
    def render(
        self,
        scene: Scene,
        method: Optional[str] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: Optional[int] = None,
        threads: Optional[int] = None,
    ) -> Image: ...
    @property
    def stats(self) -> RendererStats: ...
    @property
    def frames(self) -> int: ...
    kept_budget: int
    def clear(self) -> None: ...

def available_methods() -> list[str]: ...
def default_spp(method: str) -> int: ...
def read_volume(
    path: PathLike,
    *,
    space: Space = "LPS",
    series: Union[str, int, None] = None,
    units: Literal["", "suv"] = "",
    slice_spacing_mm: Optional[float] = None,
    frame: int = 0,
    recursive: bool = False,
) -> Tuple[np.ndarray, npt.NDArray[np.float64]]: ...
def read_volume_info(
    path: PathLike, *, series: Union[str, int, None] = None, recursive: bool = False
) -> dict[str, Any]: ...
def write_volume(volume: Volume, path: PathLike, *, compress: bool = True) -> None: ...
def read_mesh(
    path: PathLike, *, space: Optional[Space] = None, crease_angle_deg: float = 60.0
) -> Mesh: ...
def phantom_names() -> list[str]: ...
def phantom(name: str, size: int = 128) -> Volume: ...
def set_max_memory(bytes: int) -> None: ...
def max_memory() -> int: ...
def to_uint8(image: ArrayLike, linear: bool = False) -> npt.NDArray[np.uint8]: ...
def write_png(image: ArrayLike, path: PathLike, linear: bool = False) -> None: ...
def read_png(path: PathLike, linear: bool = False) -> Image: ...
def write_movie(images: Sequence[ArrayLike], path: PathLike, fps: float = 24.0) -> None: ...
def read_movie(path: PathLike) -> dict[str, Any]: ...
def encode_png(image: ArrayLike, linear: bool = False) -> bytes: ...
def compare(a: Union[ArrayLike, PathLike], b: Union[ArrayLike, PathLike]) -> dict[str, float]: ...
def error_heat_map(
    a: Union[ArrayLike, PathLike], b: Union[ArrayLike, PathLike], scale: float = 16.0
) -> Image: ...
def threshold_tf(
    threshold: float, vmax: float, symmetric: bool = True, opacity: float = 0.8,
    colormap: Optional[str] = None,
) -> dict[str, Any]: ...
def stat_map_scene(
    anatomy: Any, stat: Any, threshold: float = 3.0, *, vmax: Optional[float] = None,
    symmetric: bool = True, view: Optional[View] = None, width: int = 512, height: int = 512,
) -> Scene: ...
def stat_map(
    anatomy: Any, stat: Any, threshold: float = 3.0, *, vmax: Optional[float] = None,
    symmetric: bool = True, view: Optional[View] = None, width: int = 512, height: int = 512,
    method: Optional[str] = None, spp: Optional[int] = None,
    colorbar: Union[bool, ColourBarPosition] = False,
) -> Image: ...
def figure_scene(
    anatomy: Any, stat: Any = None, threshold: float = 3.0, *, vmax: Optional[float] = None,
    symmetric: bool = True,
) -> Scene: ...
def ortho(
    anatomy: Any, stat: Any = None, threshold: float = 3.0, *, vmax: Optional[float] = None,
    symmetric: bool = True, cut_coords: Optional[Sequence[float]] = None, height: int = 256,
    colorbar: bool = True, annotate: bool = True, crosshair: bool = True,
) -> Image: ...
def mosaic(
    anatomy: Any, stat: Any = None, threshold: float = 3.0, *, vmax: Optional[float] = None,
    symmetric: bool = True, axis: str = "z", cut_coords: Union[int, Sequence[float]] = 7,
    columns: int = 0, height: int = 256, colorbar: bool = True, annotate: bool = True,
) -> Image: ...
def glass_brain_scene(
    stat: Any, threshold: Optional[float] = None, *, anatomy: Any = None,
    vmax: Optional[float] = None,
) -> Scene: ...
def glass_brain(
    stat: Any, threshold: Optional[float] = None, *, anatomy: Any = None,
    vmax: Optional[float] = None, plot_abs: bool = True, height: int = 256,
    colorbar: bool = True, annotate: bool = True,
) -> Image: ...
def tracts_over_anatomy_scene(
    tracts: Any, anatomy: Any, *, view: View = "left", radius: float = 0.5,
    colouring: Optional[Colouring] = None, color: Optional[Sequence[float]] = None,
    value: Optional[str] = None, colormap: Optional[str] = None, opacity: float = 1.0,
    width: int = 512, height: int = 512,
) -> Scene: ...
def tracts_over_anatomy(
    tracts: Any, anatomy: Any, *, view: View = "left", radius: float = 0.5,
    colouring: Optional[Colouring] = None, color: Optional[Sequence[float]] = None,
    value: Optional[str] = None, colormap: Optional[str] = None, opacity: float = 1.0,
    width: int = 512, height: int = 512, method: Optional[str] = None, spp: Optional[int] = None,
    colorbar: Union[bool, ColourBarPosition] = False,
) -> Image: ...
def orbit_cameras(
    camera: Mapping[str, Any], frames: int = 36, degrees: float = 360.0
) -> list[dict[str, Any]]: ...
def orbit(
    scene: Scene, frames: int = 36, path: Optional[PathLike] = None, *, degrees: float = 360.0,
    method: Optional[str] = None, width: Optional[int] = None, height: Optional[int] = None,
    spp: Optional[int] = None, frame_ms: int = 80, progress: bool = True,
) -> list[Image]: ...
