"""Voxels of nibabel images and nibabel-like objects, read as intermix's file readers read them.

intermix.Volume(img) calls image_voxels; nothing here is public.
"""

import numpy as _np


def is_array_proxy(obj) -> bool:
    """An object that holds a file's raw voxels and its scaling: nibabel's ArrayProxy (img.dataobj)."""
    return all(hasattr(obj, name) for name in ("get_unscaled", "slope", "inter", "shape"))


def is_image(obj) -> bool:
    """A nibabel image or an object like one: voxels (dataobj or get_fdata) and an affine."""
    return hasattr(obj, "affine") and (hasattr(obj, "dataobj") or hasattr(obj, "get_fdata"))


def _scaled_like_the_reader(proxy):
    """The proxy's voxels as intermix's NIfTI reader gives them: the stored values when the header
    scales nothing (slope 0 or 1 and intercept 0, no copy), else float32 of value * slope + inter
    computed in double, slab by slab (nibabel's own np.asarray(dataobj) gives float64)."""
    raw = _np.asanyarray(proxy.get_unscaled())
    slope, inter = float(proxy.slope), float(proxy.inter)
    if slope == 0.0 or not _np.isfinite(slope) or (slope == 1.0 and inter == 0.0):
        return raw
    out = _np.empty(raw.shape, dtype=_np.float32, order="F")
    last = raw.ndim - 1
    for k in range(raw.shape[last]):
        index = (slice(None),) * last + (k,)
        out[index] = raw[index].astype(_np.float64) * slope + inter
    return out


def image_voxels(obj):
    """(array, affine or None): the voxels in nibabel's (i, j, k[, frames]) order and, for an
    image, its RAS affine. An image's dataobj is used when it has one (the file's own type, no
    copy), else get_fdata(dtype=float32)."""
    if is_array_proxy(obj):
        return _scaled_like_the_reader(obj), None
    affine = _np.asarray(obj.affine, dtype=_np.float64)
    data = getattr(obj, "dataobj", None)
    if data is None:
        array = obj.get_fdata(dtype=_np.float32)
    elif is_array_proxy(data):
        array = _scaled_like_the_reader(data)
    else:
        array = _np.asanyarray(data)
    return array, affine
