"""The one-liners (issue 37): each image equals the scene it stands for, written out by hand."""

import os

import numpy as np
import pytest

import intermix
from conftest import ROOT

nib = pytest.importorskip("nibabel")

RAS_TO_LPS = np.diag([-1.0, -1.0, 1.0, 1.0])
FLAIR = os.path.join(ROOT, "..", "shared", "data", "FLAIR.nii.gz")
CUBE_TF = {"points": [[0, 0, 0, 0, 0], [255, 1, 0.8, 0.6, 0.9]]}


def small_scene(camera):
    return intermix.Scene.from_dict({
        "camera": camera, "image": {"width": 40, "height": 32},
        "objects": [{"name": "ct", "type": "volume", "source": {"phantom": "ct-head", "size": 40},
                     "transfer_function": {"preset": "ct-bone"}}]})


def test_views_by_name_are_the_scene_files_camera_view():
    scene = small_scene({"eye": [0, -500, 0], "target": [0, 0, 0], "up": [0, 0, 1]})
    for view in ("left", "superior", "posterior"):
        by_hand = small_scene({"view": view}).render(method="mdvr")
        assert np.array_equal(scene.render(method="mdvr", view=view), by_hand), view
    assert scene.camera["eye"] == (0, -500, 0), "render(view=) leaves the scene's camera"
    scene.set_view("left")
    assert scene.to_dict()["camera"] == {"view": "left"}
    assert np.array_equal(scene.render(method="mdvr"), small_scene({"view": "left"}).render(
        method="mdvr"))
    with pytest.raises(ValueError, match="view 'lateral' is not one of anterior"):
        scene.set_view("lateral")


def test_orbit_frames_are_the_cameras_turned_by_hand(tmp_path, capsys):
    start = {"eye": [0, -500, 0], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 30}
    scene = small_scene(start)
    images = intermix.orbit(scene, frames=4, path=tmp_path / "spin-{}.png")
    assert "4/4" in capsys.readouterr().err
    # A quarter turn about +z (the up axis) each: -y, +x, +y, -x.
    eyes = [[0, -500, 0], [500, 0, 0], [0, 500, 0], [-500, 0, 0]]
    for n, eye in enumerate(eyes):
        by_hand = small_scene(dict(start, eye=eye)).render(method=None)
        assert np.abs(images[n] - by_hand).max() < 2e-3, n
        assert os.path.exists(tmp_path / f"spin-{n}.png")
    assert not np.array_equal(images[0], images[1])
    assert scene.camera["eye"] == (0, -500, 0), "the scene is not changed"
    with pytest.raises(ValueError, match=r"not a movie \(.mp4, .webm, .mkv\), .gif or .png"):
        intermix.orbit(scene, frames=2, path=tmp_path / "spin.avi")


def test_orbit_writes_a_gif_with_a_progress_bar(tmp_path, capsys):
    pil = pytest.importorskip("PIL.Image", reason="Pillow (python3-pil) writes GIFs")
    scene = small_scene({"eye": [0, -500, 0], "target": [0, 0, 0], "up": [0, 0, 1]})
    intermix.orbit(scene, frames=6, path=tmp_path / "spin.gif")
    err = capsys.readouterr().err
    assert "orbit [" in err and "6/6" in err
    with pil.open(tmp_path / "spin.gif") as gif:
        assert gif.n_frames == 6 and gif.size == (40, 32)


def stat_map_inputs(tmp_path):
    """A T1-like anatomy and a t-map with a positive and a negative blob, written by nibabel."""
    if os.path.exists(FLAIR):
        anatomy = nib.load(FLAIR)
    else:
        i, j, k = np.meshgrid(*[np.linspace(-1, 1, n) for n in (50, 60, 56)], indexing="ij")
        head = (200 * (i**2 + j**2 + k**2 < 0.8)).astype(np.uint8)
        affine = np.diag([2.5, 2.5, 2.5, 1.0])
        affine[:3, 3] = [-60, -75, -70]
        anatomy = nib.Nifti1Image(head, affine)
    shape = anatomy.shape
    i, j, k = np.meshgrid(*[np.arange(n) for n in shape], indexing="ij")
    c = [n // 2 for n in shape]
    t = (8 * np.exp(-((i - c[0] + 15) ** 2 + (j - c[1]) ** 2 + (k - c[2]) ** 2) / 60.0)
         - 6 * np.exp(-((i - c[0] - 15) ** 2 + (j - c[1] + 10) ** 2 + (k - c[2]) ** 2) / 40.0))
    tmap = nib.Nifti1Image(t.astype(np.float32), anatomy.affine)
    path = tmp_path / "tmap.nii.gz"
    nib.save(tmap, str(path))
    return anatomy, path, t.astype(np.float32), anatomy.affine


# threshold 3, vmax 8: the scene format's colour-map transfer function (issue 35's form).
HAND_TF = {"colormap": "cold-hot", "range": [3, 8], "threshold": 3, "symmetric": True,
           "opacity": 0.8}


def test_stat_map_is_planes_of_the_anatomy_and_the_thresholded_map(tmp_path):
    anatomy, tmap_path, t, affine = stat_map_inputs(tmp_path)
    image = intermix.stat_map(anatomy, tmap_path, threshold=3, vmax=8, width=96, height=96,
                              method="mdvr")
    # By hand: the peak |t| voxel in LPS, the box's longest side, three planes, the map's TF.
    ijk = np.unravel_index(np.argmax(np.abs(t)), t.shape)
    lps = RAS_TO_LPS @ nib.load(str(tmap_path)).affine
    peak = list((lps @ [*ijk, 1.0])[:3])
    n = anatomy.shape
    corners = np.array([[a, b, c, 1.0] for a in (-0.5, n[0] - 0.5) for b in (-0.5, n[1] - 0.5)
                        for c in (-0.5, n[2] - 0.5)]) @ (RAS_TO_LPS @ anatomy.affine).T
    side = float((corners.max(0) - corners.min(0))[:3].max())
    planes = [{"name": name, "type": "plane", "volume": "anatomy", "center": peak,
               "normal": normal, "size": side}
              for name, normal in (("axial", [0, 0, 1]), ("coronal", [0, 1, 0]),
                                   ("sagittal", [1, 0, 0]))]
    by_hand = intermix.Scene.from_dict({
        "camera": {"view": "left"},
        "image": {"width": 96, "height": 96, "background": [0, 0, 0]},
        "objects": [{"name": "anatomy", "type": "volume", "source": intermix.Volume(anatomy),
                     "visible": False}] + planes + [
                    {"name": "stat", "type": "volume", "source": {"file": str(tmap_path)},
                     "transfer_function": HAND_TF}]}).render(method="mdvr")
    assert np.abs(image - by_hand).max() < 1e-5
    reds = (image[..., 0] > 0.5) & (image[..., 2] < 0.2)
    assert reds.sum() > 5, "the positive blob shows in hot colours"


def test_glass_brain_is_a_mip_of_the_magnitude_on_white(tmp_path):
    _, tmap_path, t, _ = stat_map_inputs(tmp_path)
    image = intermix.glass_brain(tmap_path, threshold=3, vmax=8, width=96, height=96,
                                 method="mdvr")
    ras = nib.load(str(tmap_path)).affine
    magnitude = intermix.Volume(np.abs(t), ras, space="RAS")
    hot = {"colormap": "hot", "range": [3, 8], "threshold": 3, "opacity": 1}
    by_hand = intermix.Scene.from_dict({
        "camera": {"view": "left"},
        "image": {"width": 96, "height": 96, "background": [1, 1, 1]},
        "objects": [{"name": "stat", "type": "volume", "source": magnitude, "style": "mip",
                     "transfer_function": hot}]}).render(method="mdvr")
    assert np.abs(image - by_hand).max() < 1e-5
    assert image[0, 0, :3].min() > 0.99, "white where the map is below the threshold"
    assert (image[..., 2] < 0.5).sum() > 5, "hot colours where it is above"


def test_colorbar_draws_what_the_cli_draws(tmp_path, cli):
    # A colour-mapped phantom: the image with colorbar=True is the one `render --colorbar` writes,
    # and without it the bars' side is the plain render.
    doc = {"camera": {"eye": [0, -500, 0], "target": [0, 0, 0], "up": [0, 0, 1]},
           "image": {"width": 160, "height": 96},
           "objects": [{"name": "pet", "type": "volume", "units": "SUV",
                        "source": {"phantom": "pet", "size": 32},
                        "transfer_function": {"colormap": "hot", "range": [0.5, 4]}}]}
    path = tmp_path / "pet.json"
    path.write_text(__import__("json").dumps(doc))
    scene = intermix.Scene.from_file(str(path))
    with_bars = scene.render(method="mdvr", colorbar=True)
    plain = scene.render(method="mdvr")
    out = tmp_path / "cli.png"
    import subprocess
    subprocess.run([cli, "-q", "render", str(path), "-o", str(out), "--method", "mdvr",
                    "--colorbar"], check=True)
    assert np.array_equal(intermix.read_png(str(out)).to_uint8(), with_bars.to_uint8())
    assert not np.array_equal(with_bars, plain)
    with pytest.raises(TypeError, match="colorbar"):
        scene.render(colorbar="yes")
