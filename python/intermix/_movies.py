"""Movies: rendered images written as MP4 (H.264), WebM (VP9) or lossless MKV (FFV1) through the
same encoder as `intermix render --orbit` (FFmpeg's libraries, written atomically), and read back.
"""

import os
from collections.abc import Sequence

import numpy as _np

from . import _intermix


def _movie_path(path, function):
    """The path as a str, or TypeError naming `function`."""
    if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"{function}: path must be a str or os.PathLike, got "
                        f"{type(path).__name__}")
    return os.fspath(path)


def is_movie_path(path):
    """Whether `path` names a movie (.mp4, .webm, .mkv, in any case)."""
    return os.path.splitext(os.fspath(path))[1].lower() in _intermix._movie_extensions


def write_movie(images, path, fps=24.0):
    """Writes `images` (a sequence of (H, W, 4) premultiplied linear images, as renders give, all
    of one size) as a movie whose extension chooses the format: .mp4 (H.264, plays everywhere),
    .webm (VP9, for web pages) or .mkv (FFV1, lossless RGB, any size). Each frame is what
    write_png would store, over black where it is not opaque. `fps` is in [1, 240]. The file is
    written atomically: on any error nothing is left and an existing file stays as it was.
    ValueError for an unknown extension or an odd width or height with H.264 or VP9."""
    path = _movie_path(path, "write_movie")
    if isinstance(images, (str, bytes)) or not isinstance(images, (Sequence, _np.ndarray)):
        raise TypeError(f"write_movie: images must be a sequence of images, got "
                        f"{type(images).__name__}")
    _intermix._write_movie(images, path, fps)


def read_movie(path):
    """A movie's frames decoded through FFmpeg's libraries: a dict with "frames" (an (N, H, W, 3)
    uint8 array of sRGB RGB), "fps", "codec" ("h264", "vp9", "ffv1", ...) and "pixel_format"."""
    return _intermix._read_movie(_movie_path(path, "read_movie"))


def check_movie(path, width, height, fps):
    """ValueError for what write_movie would refuse, before any frame is rendered."""
    _intermix._check_movie(path, width, height, fps)

