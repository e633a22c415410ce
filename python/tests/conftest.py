"""Shared fixtures: the CLI, the examples, small scenes and volumes."""

import os
import shutil

import numpy as np
import pytest

import intermix

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLES = os.path.join(ROOT, "examples")


@pytest.fixture(scope="session")
def cli():
    """The intermix program: $INTERMIX_CLI (ctest sets it), else build/intermix."""
    path = os.environ.get("INTERMIX_CLI") or os.path.join(ROOT, "build", "intermix")
    if not os.path.exists(path):
        pytest.skip(f"no intermix program at {path}")
    return path


@pytest.fixture(scope="session")
def examples():
    return EXAMPLES


CAMERA = {"eye": [-260, -520, 120], "target": [0, 0, 5], "up": [0, 0, 1], "fov_deg": 30}
CT_TF = {
    "points": [
        [-1000, 0, 0, 0, 0],
        [-450, 0.9, 0.65, 0.55, 0.1],
        [-200, 0.9, 0.65, 0.55, 0],
        [700, 1, 0.95, 0.85, 0.6],
        [1500, 1, 1, 0.95, 0.95],
    ]
}


def blob_volume(shape=(40, 48, 56), dtype=np.int16):
    """A smooth int16-range blob in C order (k, j, i): a sphere of 700 with a softer shell."""
    k, j, i = np.meshgrid(*[np.linspace(-1, 1, n) for n in shape], indexing="ij")
    r = np.sqrt(i**2 + j**2 + k**2)
    values = np.where(r < 0.5, 700.0, np.where(r < 0.8, -300.0, -1000.0))
    values += 40.0 * np.sin(7 * i) * np.cos(5 * j)
    return values.astype(dtype)


def oblique_affine(spacing=(1.1, 0.9, 1.7), origin=(-30.0, -25.0, -40.0), degrees=12.0):
    """An index-to-world affine with a rotation about z and uneven spacing."""
    a = np.radians(degrees)
    rot = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    m = np.eye(4)
    m[:3, :3] = rot @ np.diag(spacing)
    m[:3, 3] = origin
    return m


def volume_scene(source, width=48, height=40, **extra):
    """A one-volume scene dict around `source`."""
    scene = {
        "camera": {"eye": [-200, -400, 90], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 25},
        "image": {"width": width, "height": height, "background": [0.05, 0.05, 0.08]},
        "objects": [
            {
                "name": "ct",
                "type": "volume",
                "source": source,
                "transfer_function": CT_TF,
                "shading": {"ambient": 0.2, "diffuse": 0.7, "specular": 0.3, "shininess": 32},
            }
        ],
    }
    scene.update(extra)
    return scene


def write_raw_nrrd(path, array_kji, affine_lps):
    """A raw NRRD written here, independently of intermix: (k, j, i) C-order voxels."""
    types = {np.dtype("int16"): "short", np.dtype("uint16"): "ushort",
             np.dtype("uint8"): "uchar", np.dtype("float32"): "float"}
    nk, nj, ni = array_kji.shape
    dirs = " ".join("(" + ",".join(repr(float(v)) for v in affine_lps[:3, c]) + ")" for c in range(3))
    origin = "(" + ",".join(repr(float(v)) for v in affine_lps[:3, 3]) + ")"
    header = (
        "NRRD0004\n"
        f"type: {types[array_kji.dtype]}\n"
        "dimension: 3\n"
        "space: left-posterior-superior\n"
        f"sizes: {ni} {nj} {nk}\n"
        f"space directions: {dirs}\n"
        "kinds: domain domain domain\n"
        "endian: little\n"
        "encoding: raw\n"
        f"space origin: {origin}\n\n"
    )
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(np.ascontiguousarray(array_kji).astype(array_kji.dtype.newbyteorder("<")).tobytes())


def rss_bytes():
    """Resident memory of this process (Linux /proc)."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
