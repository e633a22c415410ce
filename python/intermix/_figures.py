"""One-line figures: orbit, stat_map, ortho, mosaic, glass_brain, tracts_over_anatomy. Each builds a scene in the scene-file schema
(the *_scene functions return it, so it can be inspected, saved and changed) and renders it; no
drawing happens here that the engine does not do.
"""

import math
import numbers
import os
import sys
from collections.abc import Mapping

import numpy as _np

from ._intermix import Renderer, Scene, Streamlines, Volume, _anatomy_box, read_volume, write_png
from ._movies import check_movie, is_movie_path, write_movie


# ---- arguments ----

def _shown(value):
    """A value for a message: a huge int's first digits and its length, not all its digits."""
    text = repr(value)
    return text if len(text) <= 40 else f"{text[:16]}... ({len(text)} characters)"


def _real(value, where, lo=-math.inf, hi=math.inf):
    """`value` as a float in [lo, hi]; else TypeError or ValueError naming `where` ("orbit:
    degrees") and the value: float() said only "could not convert string to float"."""
    if isinstance(value, (bool, _np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{where} must be a real number, got {type(value).__name__}")
    try:
        f = float(value)
    except OverflowError:  # an int past a float's range
        f = math.inf
    if not math.isfinite(f):
        raise ValueError(f"{where} {_shown(value)} is not a finite number")
    if not lo <= f <= hi:
        raise ValueError(f"{where} {_shown(value)} is not in [{lo:g}, {hi:g}]")
    return f


def _int(value, where, lo, hi):
    """`value` as an int in [lo, hi]; else TypeError or ValueError naming `where` and it."""
    if isinstance(value, (bool, _np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{where} must be an int, got {type(value).__name__}")
    if not lo <= int(value) <= hi:
        raise ValueError(f"{where} {_shown(int(value))} is not in [{lo}, {hi}]")
    return int(value)


def _point(value, where):
    """Three finite real numbers as a list of floats; else TypeError or ValueError naming
    `where`."""
    if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__len__") \
            or len(value) != 3:
        raise TypeError(f"{where} must be three numbers (x, y, z), got {value!r:.80}")
    return [_real(v, f"{where}[{n}]") for n, v in enumerate(value)]


# ---- sources ----

def _volume(source, name):
    """A Volume from a Volume, a nibabel image (or dataobj), a file path, or an array whose axes
    its layout says (see Volume); ValueError naming `name` otherwise."""
    if isinstance(source, Volume):
        return source
    if isinstance(source, (str, os.PathLike)):
        array, affine = read_volume(source)
        return Volume(array, affine, axes="kji")
    try:
        return Volume(source)
    except (ValueError, TypeError) as e:
        raise type(e)(f"{name}: {e}") from None


def _peak_magnitude(volume):
    lo, hi = volume.range
    return max(abs(lo), abs(hi))


# ---- transfer functions ----

def threshold_tf(threshold, vmax, symmetric=True, opacity=0.8, colormap=None):
    """The scene format's colour-map transfer function (docs/segmentations_overlays.md): nothing
    where |value| (or value, unless symmetric) is below `threshold`, the map's colours from the
    threshold to vmax; "cold-hot" for a symmetric map (negative values in its cold half),
    else "hot"."""
    threshold = _real(threshold, "threshold_tf: threshold")
    vmax = _real(vmax, "threshold_tf: vmax")
    opacity = _real(opacity, "threshold_tf: opacity", 0.0, 1.0)
    if not vmax > threshold:
        raise ValueError(f"threshold {threshold:g} is not below the map's largest value {vmax:g}")
    return {"colormap": colormap or ("cold-hot" if symmetric else "hot"),
            "range": [threshold, vmax], "threshold": threshold, "symmetric": bool(symmetric),
            "opacity": opacity}


# ---- stat_map ----

def stat_map_scene(anatomy, stat, threshold=3.0, *, vmax=None, symmetric=True, view=None,
                   width=512, height=512):
    """The scene intermix.stat_map renders, as a Scene: the anatomy cut by three orthogonal
    planes (axial, coronal, sagittal) through the map's peak, each as large as the anatomy's box
    (its voxels above the background, _anatomy_box) and grey through the anatomy's reading
    window (its own, else its 2nd to 98th percentile), and the map as a volume showing only
    |value| >= threshold, coloured from the threshold to vmax (default: the map's largest
    magnitude), hot for positive values and cold for negative ones (symmetric). The camera
    frames what shows, from `view` (default: the side of the peak's hemisphere)."""
    anatomy = _volume(anatomy, "stat_map: anatomy")
    stat = _volume(stat, "stat_map: stat")
    peak = _peak_world(stat)
    threshold = _real(threshold, "stat_map: threshold")
    top = _real(vmax, "stat_map: vmax") if vmax is not None else _peak_magnitude(stat)
    lo, hi = (_np.array(corner) for corner in _anatomy_box(anatomy))
    centre, extent = (lo + hi) / 2, hi - lo
    if view is None:  # LPS: +x is the patient's left
        view = "left" if peak[0] > centre[0] else "right"
    objects = [{"name": "anatomy", "type": "volume", "source": anatomy, "visible": False}]
    # Each plane: through the peak along its normal, the box's extent across it.
    for name, axis, up, size in (("axial", 2, [0, -1, 0], [extent[0], extent[1]]),
                                 ("coronal", 1, [0, 0, 1], [extent[0], extent[2]]),
                                 ("sagittal", 0, [0, 0, 1], [extent[1], extent[2]])):
        normal = [0.0, 0.0, 0.0]
        normal[axis] = 1.0
        at = [float(v) for v in centre]
        at[axis] = min(max(peak[axis], lo[axis]), hi[axis])
        objects.append({"name": name, "type": "plane", "volume": "anatomy", "center": at,
                        "normal": normal, "up": up, "size": [float(v) for v in size]})
    objects.append({"name": "stat", "type": "volume", "source": stat,
                    "transfer_function": threshold_tf(threshold, top, symmetric)})
    return Scene.from_dict({
        "camera": {"view": view},
        "image": {"width": width, "height": height, "background": [0, 0, 0]},
        "objects": objects,
    })


def _largest_side(volume):
    """The longest side of the volume's world bounding box (mm): the planes' size."""
    ni, nj, nk = volume.shape
    corners = _np.array([[i, j, k, 1.0] for i in (-0.5, ni - 0.5) for j in (-0.5, nj - 0.5)
                         for k in (-0.5, nk - 0.5)])
    world = corners @ volume.lps_affine.T
    return float((world.max(axis=0) - world.min(axis=0))[:3].max())


def _peak_world(volume):
    """The LPS world position of the voxel of largest magnitude (NaN ignored)."""
    voxels = volume.voxels  # (k, j, i)
    magnitude = _np.abs(voxels.astype(_np.float32, copy=False))
    k, j, i = _np.unravel_index(_np.nanargmax(magnitude), voxels.shape)
    return [float(v) for v in (volume.lps_affine @ [i, j, k, 1.0])[:3]]


def _colorbar_position(colorbar, function):
    """A one-liner's colorbar= as Scene.render takes it: True puts the bars beside the image."""
    if colorbar is True:
        return "outside"
    if colorbar is False or colorbar is None or isinstance(colorbar, str):
        return colorbar
    raise TypeError(f"{function}: colorbar must be True, False or a position, "
                    f"got {type(colorbar).__name__}")


def stat_map(anatomy, stat, threshold=3.0, *, vmax=None, symmetric=True, view=None,
             width=512, height=512, method=None, spp=None, colorbar=False):
    """A statistical map over an anatomical image in one call, in 3-D: stat_map_scene(...)
    rendered. `anatomy` and `stat` are Volumes, nibabel images or file paths. colorbar=True
    draws the map's colour bar beside the image (which grows to the right; or a position:
    "top-right", ...). Returns an intermix.Image (image.to_uint8() for display)."""
    scene = stat_map_scene(anatomy, stat, threshold, vmax=vmax, symmetric=symmetric, view=view,
                           width=width, height=height)
    return scene.render(method=method, spp=spp,
                        colorbar=_colorbar_position(colorbar, "stat_map"))


# ---- 2-D figures: ortho, mosaic, glass_brain ----

# nilearn's display modes as axes: x cuts are sagittal, y coronal, z axial.
_AXES = {"x": "sagittal", "y": "coronal", "z": "axial", "sagittal": "sagittal",
         "coronal": "coronal", "axial": "axial"}


def _map_name(source):
    """A map's name in figures (its colour bar's title): its file's name without extensions,
    as `intermix figure` names it, else "stat"."""
    if isinstance(source, (str, os.PathLike)):
        name = os.path.basename(os.fspath(source))
        for _ in range(2):
            name = os.path.splitext(name)[0]
        return name or "stat"
    return "stat"


def figure_scene(anatomy, stat=None, threshold=3.0, *, vmax=None, symmetric=True):
    """The scene intermix.ortho and intermix.mosaic draw: the anatomy (grey through its reading
    window) and, when given, the map coloured from the threshold to vmax as stat_map colours
    it. Scene.figure(...) draws it."""
    objects = [{"name": "anatomy", "type": "volume", "source": _volume(anatomy, "anatomy")}]
    if stat is not None:
        name = _map_name(stat)
        stat = _volume(stat, "stat")
        threshold = _real(threshold, "figure: threshold")
        top = _real(vmax, "figure: vmax") if vmax is not None else _peak_magnitude(stat)
        objects.append({"name": name, "type": "volume", "source": stat,
                        "transfer_function": threshold_tf(threshold, top, symmetric)})
    return Scene.from_dict({"objects": objects})


def _ras_to_lps(point, where):
    x, y, z = _point(point, where)
    return [-x, -y, z]


def ortho(anatomy, stat=None, threshold=3.0, *, vmax=None, symmetric=True, cut_coords=None,
          height=256, colorbar=True, annotate=True, crosshair=True):
    """Three cuts (sagittal, coronal, axial) through `cut_coords` (RAS mm, as nilearn's; default:
    the map's peak, else the anatomy's centre), as nilearn's plot_stat_map (or plot_anat without
    a map) draws them: the anatomy in grey, the map above |threshold| in cold-hot colours,
    the crosshair, orientation letters, each cut's coordinate and the colour bar beside the
    panels. Returns an intermix.Image; `intermix figure ortho` draws the same."""
    scene = figure_scene(anatomy, stat, threshold, vmax=vmax, symmetric=symmetric)
    cut = None if cut_coords is None else _ras_to_lps(cut_coords, "ortho: cut_coords")
    return scene.figure("ortho", cut=cut, height=height, colorbar=colorbar, annotate=annotate,
                        crosshair=crosshair)


def mosaic(anatomy, stat=None, threshold=3.0, *, vmax=None, symmetric=True, axis="z",
           cut_coords=7, columns=0, height=256, colorbar=True, annotate=True):
    """Cuts along one axis ("x"/"sagittal", "y"/"coronal", "z"/"axial"), as nilearn's
    display_mode="x"/"y"/"z" and mosaic draw them: `cut_coords` an int (that many cuts spread
    over where the map shows, else over the anatomy) or the cuts' RAS coordinates along the
    axis; `columns` panels per row (0: one row up to 8). Returns an intermix.Image; `intermix
    figure mosaic` draws the same."""
    if axis not in _AXES:
        raise ValueError(f"mosaic: axis '{axis}' is not one of {', '.join(_AXES)}")
    axis = _AXES[axis]
    scene = figure_scene(anatomy, stat, threshold, vmax=vmax, symmetric=symmetric)
    if isinstance(cut_coords, (int, _np.integer)) and not isinstance(cut_coords, bool):
        slices = _int(cut_coords, "mosaic: cut_coords", 1, 64)
        return scene.figure("mosaic", axis=axis, slices=slices, columns=columns,
                            height=height, colorbar=colorbar, annotate=annotate)
    sign = 1.0 if axis == "axial" else -1.0  # RAS to LPS along x and y
    if isinstance(cut_coords, (str, bytes)) or not hasattr(cut_coords, "__iter__"):
        raise TypeError(f"mosaic: cut_coords must be an int or a list of coordinates, got "
                        f"{type(cut_coords).__name__}")
    cuts = [sign * _real(c, f"mosaic: cut_coords[{n}]") for n, c in enumerate(cut_coords)]
    return scene.figure("mosaic", axis=axis, cuts=cuts, columns=columns, height=height,
                        colorbar=colorbar, annotate=annotate)


def glass_brain_scene(stat, threshold=None, *, anatomy=None, vmax=None):
    """The scene intermix.glass_brain draws: the anatomy when given (its outline), then the map
    coloured hot from the threshold (default: 0, every value above it) to vmax (default: its
    largest magnitude)."""
    name = _map_name(stat)
    stat = _volume(stat, "glass_brain: stat")
    top = _real(vmax, "glass_brain: vmax") if vmax is not None else _peak_magnitude(stat)
    low = 0.0 if threshold is None else _real(threshold, "glass_brain: threshold")
    objects = []
    if anatomy is not None:
        objects.append({"name": "anatomy", "type": "volume",
                        "source": _volume(anatomy, "glass_brain: anatomy")})
    objects.append({"name": name, "type": "volume", "source": stat,
                    "transfer_function": threshold_tf(low, top, symmetric=False, opacity=1.0)})
    return Scene.from_dict({"objects": objects})


def glass_brain(stat, threshold=None, *, anatomy=None, vmax=None, plot_abs=True, height=256,
                colorbar=True, annotate=True):
    """A glass brain in one call, as nilearn's plot_glass_brain: three projections (sagittal,
    coronal, axial) of the map's largest |value| (plot_abs, the default; else its largest
    value) in hot colours on white, over the outline of `anatomy` (a Volume, nibabel image or
    path: its voxels above the background, seen the same way) when given, with the colour bar
    beside them. Returns an intermix.Image; `intermix figure glass` draws the same."""
    scene = glass_brain_scene(stat, threshold, anatomy=anatomy, vmax=vmax)
    return scene.figure("glass", plot_abs=plot_abs, height=height, colorbar=colorbar,
                        annotate=annotate)


# ---- tracts_over_anatomy ----

# Each view's world axis (LPS: +x left, +y posterior, +z superior) and the side the camera is on.
_VIEW_AXES = {"left": (0, 1.0), "right": (0, -1.0), "posterior": (1, 1.0),
              "anterior": (1, -1.0), "superior": (2, 1.0), "inferior": (2, -1.0)}


def _volume_bounds(volume):
    """The volume's world (LPS) bounding box over its voxel centres: (lo, hi)."""
    ni, nj, nk = volume.shape
    corners = _np.array([[i, j, k, 1.0] for i in (0, ni - 1) for j in (0, nj - 1)
                         for k in (0, nk - 1)])
    world = (corners @ volume.lps_affine.T)[:, :3]
    return world.min(axis=0), world.max(axis=0)


def tracts_over_anatomy_scene(tracts, anatomy, *, view="left", radius=0.5, colouring=None,
                              color=None, value=None, colormap=None, opacity=1.0,
                              width=512, height=512):
    """The scene intermix.tracts_over_anatomy renders, as a Scene: the tractogram as tubes
    (Scene.add_streamlines: coloured by direction unless `colouring`, `color` or `value` say
    otherwise) in front of one slice of the anatomy, perpendicular to `view` and just behind
    the tracts as the camera sees them (the far side of their bounding box, within the
    anatomy), grey over the anatomy's own range, on black. `tracts` is an intermix.Streamlines,
    a tractogram file path, a nibabel Tractogram or ArraySequence, or a list of (n, 3) RAS
    arrays; `anatomy` a Volume, a nibabel image or a file path."""
    if view not in _VIEW_AXES:
        raise ValueError(f"tracts_over_anatomy: view '{view}' is not one of "
                         f"{', '.join(_VIEW_AXES)}")
    radius = _real(radius, "tracts_over_anatomy: radius", 0.0, 1e3)
    if not isinstance(tracts, Streamlines):
        tracts = Streamlines(tracts)
    if tracts.count == 0 or len(tracts.points) == 0:
        raise ValueError("tracts_over_anatomy: the tractogram has no streamlines")
    anatomy = _volume(anatomy, "tracts_over_anatomy: anatomy")
    axis, camera_side = _VIEW_AXES[view]
    lo, hi = _volume_bounds(anatomy)
    points = tracts.points
    far = points[:, axis].min() if camera_side > 0 else points[:, axis].max()
    center = (lo + hi) / 2
    # Behind the tubes (their radius and a millimetre), kept inside the anatomy.
    center[axis] = min(max(far - camera_side * (radius + 1.0), lo[axis]), hi[axis])
    normal = [0.0, 0.0, 0.0]
    normal[axis] = 1.0
    scene = Scene.from_dict({
        "camera": {"view": view},
        "image": {"width": width, "height": height, "background": [0, 0, 0]},
        "objects": [
            {"name": "anatomy", "type": "volume", "source": anatomy, "visible": False},
            {"name": "slice", "type": "plane", "volume": "anatomy",
             "center": [float(v) for v in center], "normal": normal,
             "size": _largest_side(anatomy)},
        ],
    })
    scene.add_streamlines(tracts, radius=radius, colouring=colouring, color=color, value=value,
                          colormap=colormap, opacity=opacity, name="tracts")
    return scene


def tracts_over_anatomy(tracts, anatomy, *, view="left", radius=0.5, colouring=None, color=None,
                        value=None, colormap=None, opacity=1.0, width=512, height=512,
                        method=None, spp=None, colorbar=False):
    """A tractogram over an anatomical image in one call: tracts_over_anatomy_scene(...)
    rendered (tubes coloured by direction in front of an anatomical slice, seen from `view`).
    `tracts` is a file path (.trk, .tck, .trx, .tt.gz, .vtk), an intermix.Streamlines, a
    nibabel Tractogram or ArraySequence or a list of (n, 3) RAS arrays; `anatomy` a file
    path, a nibabel image or a Volume. colorbar=True draws the tracts' colour bar (when they
    are coloured by a value) beside the image. Returns an intermix.Image (image.to_uint8() for
    display)."""
    scene = tracts_over_anatomy_scene(tracts, anatomy, view=view, radius=radius,
                                      colouring=colouring, color=color, value=value,
                                      colormap=colormap, opacity=opacity, width=width,
                                      height=height)
    return scene.render(method=method, spp=spp,
                        colorbar=_colorbar_position(colorbar, "tracts_over_anatomy"))


# ---- orbit ----

# As `intermix render --orbit N --orbit-degrees D` takes them.
_MAX_FRAMES = 100000
_MAX_DEGREES = 36000.0


def orbit_cameras(camera, frames=36, degrees=360.0):
    """`frames` camera blocks turning `camera` (a dict with eye, target, up) about the axis
    through its target along its up vector, evenly over `degrees` (the last frame stops one
    step short of a full turn, so a looping GIF does not repeat a frame)."""
    if not isinstance(camera, Mapping) or any(k not in camera for k in ("eye", "target", "up")):
        hint = " (a Scene's is scene.camera)" if isinstance(camera, Scene) else ""
        raise TypeError(f"orbit_cameras: camera must be a dict with eye, target and up{hint}, "
                        f"got {type(camera).__name__}")
    frames = _int(frames, "orbit_cameras: frames", 1, _MAX_FRAMES)
    degrees = _real(degrees, "orbit_cameras: degrees", -_MAX_DEGREES, _MAX_DEGREES)
    eye = _np.asarray(_point(camera["eye"], "orbit_cameras: camera['eye']"))
    target = _np.asarray(_point(camera["target"], "orbit_cameras: camera['target']"))
    axis = _np.asarray(_point(camera["up"], "orbit_cameras: camera['up']"))
    if not _np.linalg.norm(axis) > 0:
        raise ValueError("orbit_cameras: camera['up'] is [0, 0, 0], not a direction")
    axis = axis / _np.linalg.norm(axis)
    offset = eye - target
    cameras = []
    for n in range(frames):
        a = _np.radians(degrees) * n / frames
        # Rodrigues: the offset turned by a about the axis.
        turned = (offset * _np.cos(a) + _np.cross(axis, offset) * _np.sin(a)
                  + axis * _np.dot(axis, offset) * (1 - _np.cos(a)))
        block = dict(camera)
        block["eye"] = [float(v) for v in target + turned]
        block["target"] = [float(v) for v in target]
        block["up"] = [float(v) for v in axis]
        cameras.append(block)
    return cameras


class _Progress:
    """A one-line progress bar on stderr: 'orbit [#####.....] 12/36 3.1 s'."""

    def __init__(self, total, label, enabled):
        self.total, self.label, self.enabled = total, label, enabled
        import time
        self._time = time.monotonic
        self._start = self._time()

    def update(self, done):
        if not self.enabled:
            return
        width = 30
        filled = width * done // self.total
        sys.stderr.write(f"\r{self.label} [{'#' * filled}{'.' * (width - filled)}] "
                         f"{done}/{self.total} {self._time() - self._start:.1f} s")
        if done == self.total:
            sys.stderr.write("\n")
        sys.stderr.flush()


def orbit(scene, frames=36, path=None, *, degrees=360.0, method=None, width=None, height=None,
          spp=None, frame_ms=80, progress=True):
    """Renders `frames` images with the camera turning about the scene's up axis through its
    target (a turntable), with a progress bar on stderr (progress=False for none), and returns
    them as a list of intermix.Image. The scene is not changed.

    `path`: None (only return them), a movie (NAME.mp4: H.264, NAME.webm: VP9, NAME.mkv: lossless
    FFV1; `frame_ms` per frame, through the encoder of `intermix render --orbit`, see
    write_movie), NAME.gif (an animated GIF, `frame_ms` per frame, looping; needs Pillow,
    Debian's python3-pil), or a PNG name: NAME.png writes NAME-000.png, NAME-001.png, ... and a
    name holding {} (frame-{:03d}.png) is formatted with the index."""
    if not isinstance(scene, Scene):
        raise TypeError(f"orbit: scene must be an intermix.Scene, got {type(scene).__name__}")
    frames = _int(frames, "orbit: frames", 1, _MAX_FRAMES)
    degrees = _real(degrees, "orbit: degrees", -_MAX_DEGREES, _MAX_DEGREES)
    writer = _frame_writer(path, frame_ms) if path is not None else None
    turning = scene.copy()
    renderer = Renderer()
    bar = _Progress(frames, "orbit", progress)
    images = []
    for n, camera in enumerate(orbit_cameras(turning.camera, frames, degrees)):
        turning.set("camera", camera)
        images.append(renderer.render(turning, method=method, width=width, height=height,
                                      spp=spp))
        if n == 0 and isinstance(writer, _MovieWriter):
            writer.check(images[0])  # a movie's size errors come after one frame, not all
        bar.update(n + 1)
    if writer is not None:
        writer(images)
    return images


class _MovieWriter:
    """Writes the frames as a movie; check() refuses what the encoder would, after one frame."""

    def __init__(self, path, fps):
        self.path, self.fps = path, fps

    def check(self, image):
        check_movie(self.path, image.shape[1], image.shape[0], self.fps)

    def __call__(self, images):
        write_movie(images, self.path, self.fps)


def _frame_writer(path, frame_ms):
    """A function writing the frames to `path`; errors (no Pillow, a bad name) come before any
    frame is rendered."""
    path = os.fspath(path)
    lower = path.lower()
    frame_ms = _real(frame_ms, "orbit: frame_ms", 1.0, 60000.0)
    if is_movie_path(path):
        if isinstance(frame_ms, bool) or not isinstance(frame_ms, (int, float, _np.number)) \
                or not 1000.0 / 240 <= frame_ms <= 1000.0:
            raise ValueError(f"orbit: frame_ms must be a number in [{1000 / 240:.3g}, 1000] "
                             f"for a movie, got {frame_ms!r}")
        return _MovieWriter(path, 1000.0 / float(frame_ms))
    if lower.endswith(".gif"):
        try:
            from PIL import Image as PilImage
        except ImportError:
            raise ImportError(
                "orbit: writing a GIF needs Pillow (Debian: apt-get install python3-pil); or "
                "write PNG frames with path='frame-{:03d}.png'") from None

        def write_gif(images):
            pictures = [PilImage.fromarray(image.to_uint8()[..., :3]) for image in images]
            pictures[0].save(path, save_all=True, append_images=pictures[1:],
                             duration=frame_ms, loop=0)

        return write_gif
    if lower.endswith(".png"):
        pattern = path if "{" in path else path[:-4] + "-{:03d}.png"

        def write_pngs(images):
            for n, image in enumerate(images):
                write_png(image, pattern.format(n))

        return write_pngs
    raise ValueError(f"orbit: path '{path}' is not a movie (.mp4, .webm, .mkv), .gif or .png "
                     f"name")
