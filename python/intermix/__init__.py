"""intermix: render scenes that fuse volumes, meshes and MPR planes, from numpy.

    import numpy as np, intermix
    ct = intermix.Volume(array, affine, axes="kji")     # numpy voxels [k, j, i], 4x4 LPS affine
    t1 = intermix.Volume(nibabel.load("t1.nii.gz"))     # a nibabel image, as the file reads
    scene = intermix.Scene.from_dict({
        "camera": {"eye": [0, -600, 0], "target": [0, 0, 0], "up": [0, 0, 1]},
        "objects": [{"name": "ct", "type": "volume", "source": ct,
                     "transfer_function": {"preset": "ct-bone"}}]})
    image = scene.render(method="mdvr", width=256, height=256, view="left")
    plt.imshow(image.to_uint8())                                 # the sRGB display image
    intermix.write_png(image, "ct.png")

Scene (from_file, from_files, from_dict, set, set_view, add_volume, add_mesh, add_plane,
add_streamlines, to_dict, render, figure, show: the viewer in a notebook cell, a View), Volume,
Mesh, Streamlines (tractograms from files, nibabel or DIPY), Renderer (stage reuse),
read_volume, read_mesh, write_volume, phantom, compare, to_uint8, write_png, read_png,
write_movie, read_movie, available_methods, set_max_memory; one-line figures: orbit (to MP4,
WebM, GIF or PNG frames), stat_map, ortho, mosaic, glass_brain, tracts_over_anatomy (and their
*_scene, figure_scene). Errors: ValueError (a scene or value at fault), OSError (a file that
cannot be read or written), MemoryError (an input over the memory budget, or more than the
machine gives), RuntimeError (a render that failed), each with the library's one-line message.
docs/python.md has the details.
"""

import numpy as _np

from ._intermix import __version__  # CMake's project version
from ._intermix import (
    Mesh,
    Renderer,
    RendererStats,
    Scene,
    Streamlines,
    View,
    Volume,
    _set_image_type,
    available_methods,
    compare,
    default_spp,
    encode_png,
    error_heat_map,
    max_memory,
    phantom,
    phantom_names,
    read_mesh,
    read_png,
    read_volume,
    read_volume_info,
    set_max_memory,
    to_uint8,
    write_png,
    write_volume,
)
from ._figures import (
    figure_scene,
    glass_brain,
    glass_brain_scene,
    orbit,
    orbit_cameras,
    mosaic,
    ortho,
    stat_map,
    stat_map_scene,
    threshold_tf,
    tracts_over_anatomy,
    tracts_over_anatomy_scene,
)
from ._movies import read_movie, write_movie

__all__ = [
    "Image",
    "Mesh",
    "Renderer",
    "RendererStats",
    "Scene",
    "Streamlines",
    "View",
    "Volume",
    "available_methods",
    "compare",
    "default_spp",
    "encode_png",
    "error_heat_map",
    "figure_scene",
    "glass_brain",
    "glass_brain_scene",
    "max_memory",
    "mosaic",
    "orbit",
    "orbit_cameras",
    "ortho",
    "phantom",
    "phantom_names",
    "read_mesh",
    "read_movie",
    "read_png",
    "read_volume",
    "read_volume_info",
    "set_max_memory",
    "stat_map",
    "stat_map_scene",
    "threshold_tf",
    "to_uint8",
    "tracts_over_anatomy",
    "tracts_over_anatomy_scene",
    "write_movie",
    "write_png",
    "write_volume",
]


class Image(_np.ndarray):
    """A rendered image: an (H, W, 4) float32 numpy array of premultiplied linear RGBA.

    Its values are linear light, not display values: show it with plt.imshow(image.to_uint8()),
    the sRGB image a PNG holds (imshow of the floats shows it too dark). It is an ndarray in
    every respect (slicing, arithmetic and numpy functions work as usual); it adds to_uint8(),
    save() and a PNG representation, so a notebook shows it as a picture. Whatever is no longer
    an (H, W, 4) image (image[..., 0], a mean, a row of pixels) is a plain ndarray;
    np.asarray(image) gives the base ndarray.
    """

    def __getitem__(self, key):
        item = super().__getitem__(key)
        if isinstance(item, _np.ndarray) and (item.ndim != 3 or item.shape[2] != 4):
            return item.view(_np.ndarray)
        return item

    def to_uint8(self, linear: bool = False) -> _np.ndarray:
        """The sRGB display image as an (H, W, 4) uint8 array (straight alpha), as PNG stores it."""
        return to_uint8(self, linear)

    def save(self, path, linear: bool = False) -> None:
        """Writes the image as PNG (see intermix.write_png)."""
        write_png(self, path, linear)

    def __array_wrap__(self, obj, context=None):
        # Results that are no image (sums, means, single channels) are plain arrays or scalars.
        if obj.ndim == 0:
            return obj[()]
        if obj.ndim != 3 or obj.shape[2] != 4:
            return obj.view(_np.ndarray)
        return super().__array_wrap__(obj, context)

    def _repr_png_(self):
        if self.ndim != 3 or self.shape[2] != 4 or self.dtype.kind != "f":
            return None  # a slice or a reduction of an image is no longer one
        return encode_png(self)


_set_image_type(Image)

Scene.__module__ = Volume.__module__ = Mesh.__module__ = Streamlines.__module__ = __name__
Renderer.__module__ = RendererStats.__module__ = View.__module__ = __name__
