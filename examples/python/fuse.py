#!/usr/bin/python3
"""Fuses a CT-like and a PET-like volume made in numpy with a mesh, renders and saves a PNG.

The CT is a 1 x 1 x 1.5 mm grid of 160 x 160 x 100 voxels (int16, Hounsfield-like); the PET is
a coarser 4 mm grid, rotated 10 degrees about z and shifted, with two hot spots (float32). Each
has its own 4x4 index-to-world affine (LPS, mm); the arrays are C-ordered [k, j, i] (axes="kji")
and used without a copy. A sphere mesh marks one hot spot.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/fuse.py -o fuse.png

Debian's /usr/bin/python3 is named: the package is built for it, and it has numpy (python3-numpy);
another python3 first on PATH (pyenv, a venv without system packages) may have neither.
"""

import argparse
import sys
import time

try:
    import numpy as np
except ImportError as e:
    print(f"fuse.py: {e}: run it with Debian's /usr/bin/python3 (apt-get install python3-numpy), "
          f"not {sys.executable}", file=sys.stderr)
    sys.exit(77)

try:
    import intermix
except ImportError as e:  # run from the project without PYTHONPATH=build/python
    print(f"fuse.py: {e}; build first (scripts/build), then PYTHONPATH=build/python", file=sys.stderr)
    sys.exit(77)


def grid(shape_kji, affine):
    """World x, y, z (mm) of every voxel centre of a (k, j, i) grid."""
    k, j, i = np.meshgrid(*[np.arange(n, dtype=np.float32) for n in shape_kji], indexing="ij")
    ijk1 = np.stack([i, j, k, np.ones_like(i)], axis=-1)
    xyz = ijk1 @ affine.T.astype(np.float32)
    return xyz[..., 0], xyz[..., 1], xyz[..., 2]


def ct_volume():
    shape = (100, 160, 160)  # k, j, i
    affine = np.array([[1.0, 0, 0, -80], [0, 1.0, 0, -80], [0, 0, 1.5, -75], [0, 0, 0, 1]])
    x, y, z = grid(shape, affine)
    r = np.sqrt((x / 70) ** 2 + (y / 60) ** 2 + (z / 70) ** 2)  # an ellipsoidal "body"
    hu = np.full(shape, -1000.0, np.float32)
    hu[r < 1.0] = 40.0                                    # soft tissue
    hu[(r > 0.9) & (r < 1.0)] = 900.0                     # a bony shell
    spine = np.sqrt((x / 10) ** 2 + ((y - 30) / 10) ** 2) < 1.0
    hu[spine & (r < 1.0)] = 700.0                         # a "spine" along z
    return hu.astype(np.int16), affine


def pet_volume():
    shape = (40, 40, 40)
    a = np.radians(10)
    rotation = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    affine = np.eye(4)
    affine[:3, :3] = rotation @ np.diag([4.0, 4.0, 4.0])
    affine[:3, 3] = [-70, -85, -70]
    x, y, z = grid(shape, affine)
    spots = [((25, -10, 20), 12.0, 10.0), ((-30, 15, -15), 8.0, 6.0)]
    suv = np.full(shape, 0.5, np.float32)
    for (cx, cy, cz), radius, peak in spots:
        d2 = (x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2
        suv += peak * np.exp(-d2 / (2 * (radius / 2) ** 2)).astype(np.float32)
    return suv, affine


def sphere_mesh(radius, centre, n=32):
    """A UV sphere as numpy vertices and triangles (outward, counter-clockwise)."""
    theta = np.linspace(0, np.pi, n // 2 + 1)
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    normals = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3)
    rows, cols = len(theta), len(phi)
    tris = []
    for r in range(rows - 1):
        for c in range(cols):
            a, b = r * cols + c, r * cols + (c + 1) % cols
            tris += [[a, a + cols, b], [b, a + cols, b + cols]]
    return intermix.Mesh(normals * radius + centre, np.array(tris), normals=normals)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", default="fuse.png")
    parser.add_argument("--method", default="zslab-hybrid", help="rendering method")
    parser.add_argument("--size", type=int, default=384, help="image width and height")
    args = parser.parse_args()

    start = time.perf_counter()
    ct, ct_affine = ct_volume()
    pet, pet_affine = pet_volume()
    scene = intermix.Scene.from_dict({
        "camera": {"eye": [-200, -290, 100], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 30},
        "image": {"width": args.size, "height": args.size, "background": [0.05, 0.05, 0.08]},
        "objects": [
            {"name": "ct", "type": "volume",
             "source": intermix.Volume(ct, ct_affine, axes="kji"),
             "transfer_function": {"points": [[-1000, 0, 0, 0, 0], [-100, 0.9, 0.7, 0.6, 0],
                                              [40, 0.9, 0.7, 0.6, 0.003], [300, 1, 1, 0.9, 0.003],
                                              [700, 1, 1, 0.95, 0.05], [900, 1, 1, 0.95, 0.02]]},
             "shading": {"ambient": 0.3, "diffuse": 0.7, "specular": 0.2, "shininess": 24}},
            {"name": "pet", "type": "volume",
             "source": intermix.Volume(pet, pet_affine, axes="kji"),
             "transfer_function": {"points": [[0, 0, 0, 0, 0], [2, 1, 0.2, 0, 0],
                                              [5, 1, 0.5, 0, 0.2], [10, 1, 1, 0.3, 0.8]]}},
        ],
    })
    scene.add_mesh("marker", sphere_mesh(14, (25, -10, 20)),
                   material={"color": [0.3, 0.6, 1.0], "opacity": 0.35})
    built = time.perf_counter()
    image = scene.render(method=args.method)
    rendered = time.perf_counter()
    intermix.write_png(image, args.output)
    print(f"fuse.py: CT {ct.shape[::-1]} int16 + PET {pet.shape[::-1]} float32 + mesh; "
          f"scene {built - start:.2f} s, {args.method} {image.shape[1]}x{image.shape[0]} "
          f"in {rendered - built:.2f} s -> {args.output}")


if __name__ == "__main__":
    main()
