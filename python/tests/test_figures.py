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
    # By hand: the peak |t| voxel in LPS, the anatomy's box (its voxels above the background),
    # three planes through the peak as large as the box, the map's TF, the peak's side.
    ijk = np.unravel_index(np.argmax(np.abs(t)), t.shape)
    lps = RAS_TO_LPS @ nib.load(str(tmap_path)).affine
    peak = (lps @ [*ijk, 1.0])[:3]
    lo, hi = (np.array(c) for c in intermix._intermix._anatomy_box(intermix.Volume(anatomy)))
    centre, size = (lo + hi) / 2, hi - lo
    planes = []
    for name, axis, up, extent in (("axial", 2, [0, -1, 0], [size[0], size[1]]),
                                   ("coronal", 1, [0, 0, 1], [size[0], size[2]]),
                                   ("sagittal", 0, [0, 0, 1], [size[1], size[2]])):
        at = centre.copy()
        at[axis] = peak[axis]
        normal = [0, 0, 0]
        normal[axis] = 1
        planes.append({"name": name, "type": "plane", "volume": "anatomy", "center": list(at),
                       "normal": normal, "up": up, "size": extent})
    by_hand = intermix.Scene.from_dict({
        "camera": {"view": "left" if peak[0] > centre[0] else "right"},
        "image": {"width": 96, "height": 96, "background": [0, 0, 0]},
        "objects": [{"name": "anatomy", "type": "volume", "source": intermix.Volume(anatomy),
                     "visible": False}] + planes + [
                    {"name": "stat", "type": "volume", "source": {"file": str(tmap_path)},
                     "transfer_function": HAND_TF}]}).render(method="mdvr")
    assert np.abs(image - by_hand).max() < 1e-5
    reds = (image[..., 0] > 0.5) & (image[..., 2] < 0.2)
    assert reds.sum() > 5, "the positive blob shows in hot colours"


MNI = os.path.join(ROOT, "..", "shared", "data", "neuro", "volumes", "avg152T1_RL_nifti.nii.gz")


def mni_inputs(tmp_path):
    """The MNI template (avg152T1) and a t-map in its space with a right-motor peak (7.5) and a
    negative left cerebellar blob; skips without ../shared/data."""
    if not os.path.exists(MNI):
        pytest.skip("needs ../shared/data/neuro/volumes/avg152T1_RL_nifti.nii.gz")
    template = nib.load(MNI)
    ijk = np.stack(np.meshgrid(*[np.arange(n) for n in template.shape[:3]], indexing="ij"))
    xyz = np.einsum("ab,b...->a...", template.affine[:3, :3], ijk)
    xyz += template.affine[:3, 3][:, None, None, None]

    def blob(centre, sigma, amplitude):
        d2 = sum((xyz[a] - centre[a]) ** 2 for a in range(3))
        return amplitude * np.exp(-d2 / (2 * sigma**2))

    t = blob((38, -22, 56), 8, 7.5) + blob((-30, -60, -20), 6, -5.0)
    path = tmp_path / "tmap.nii.gz"
    nib.save(nib.Nifti1Image(t.astype(np.float32), template.affine), str(path))
    return MNI, path


def test_stat_map_defaults_show_the_anatomy_framed_and_windowed(tmp_path):
    anatomy, tmap = mni_inputs(tmp_path)
    scene = intermix.stat_map_scene(anatomy, tmap)
    doc = scene.to_dict()
    # The view faces the peak's hemisphere (x = +38 RAS: the patient's right).
    assert doc["camera"]["view"] == "right"
    # The planes lie inside the anatomy's box, through the peak.
    lo, hi = (np.array(c) for c in intermix._intermix._anatomy_box(intermix.Volume(nib.load(anatomy))))
    for plane in [o for o in doc["objects"] if o["type"] == "plane"]:
        assert np.all(np.array(plane["center"]) >= lo - 1e-6)
        assert np.all(np.array(plane["center"]) <= hi + 1e-6)
        assert max(plane["size"]) <= (hi - lo).max() + 1e-6
    image = intermix.stat_map(anatomy, tmap, method="mdvr")
    rgb = image.to_uint8()[..., :3].astype(int)
    # The anatomy's window: the planes' greys span at least 80% of the display range.
    grey = (np.abs(rgb[..., 0] - rgb[..., 2]) < 3) & (rgb.sum(-1) > 0)
    values = rgb[grey][:, 0]
    assert np.percentile(values, 99.5) - np.percentile(values, 0.5) >= 0.8 * 255
    # Framed on the anatomy: what shows spans at least 60% of the frame's short side.
    ys, xs = np.nonzero(rgb.sum(-1) > 30)
    assert min(xs.ptp(), ys.ptp()) >= 0.6 * 512


def test_colour_bars_stand_beside_the_one_liners_images(tmp_path):
    anatomy, tmap = mni_inputs(tmp_path)
    plain = intermix.stat_map(anatomy, tmap, width=128, height=128, method="mdvr")
    barred = intermix.stat_map(anatomy, tmap, width=128, height=128, method="mdvr",
                               colorbar=True)
    assert barred.shape[0] == 128 and barred.shape[1] > 128
    # The render's pixels are untouched: the bar stands on the widened canvas.
    assert np.array_equal(barred[:, :128], plain)
    with pytest.raises(ValueError, match="colorbar 'middle' is not one of top-right"):
        intermix.stat_map(anatomy, tmap, width=64, height=64, colorbar="middle")


def test_ortho_and_mosaic_are_the_figures_intermix_figure_draws(tmp_path, cli):
    anatomy, tmap = mni_inputs(tmp_path)
    import subprocess
    for kind, python in (("ortho", lambda: intermix.ortho(anatomy, tmap)),
                         ("mosaic", lambda: intermix.mosaic(anatomy, tmap, cut_coords=5)),
                         ("glass", lambda: intermix.glass_brain(tmap, 3, anatomy=anatomy))):
        out = tmp_path / f"{kind}.png"
        extra = ["--slices", "5"] if kind == "mosaic" else []
        subprocess.run([cli, "-q", "figure", kind, anatomy, str(tmap), "-o", str(out)] + extra,
                       check=True)
        assert np.array_equal(intermix.read_png(str(out)).to_uint8(), python().to_uint8()), kind
    # Cut coordinates are RAS, as nilearn's: x = 38 is the sagittal plane through the peak.
    image = intermix.ortho(anatomy, tmap, cut_coords=(38, -22, 56), colorbar=False,
                           annotate=False, crosshair=False)
    auto = intermix.ortho(anatomy, tmap, colorbar=False, annotate=False, crosshair=False)
    assert np.array_equal(image, auto)
    sagittal_left = intermix.mosaic(anatomy, tmap, axis="x", cut_coords=[38], colorbar=False,
                                    annotate=False)
    assert (sagittal_left[..., 0] > 0.5).any() and (sagittal_left[..., 2] < 0.2).any()
    with pytest.raises(ValueError, match="axis 'w' is not one of"):
        intermix.mosaic(anatomy, tmap, axis="w")


def test_glass_brain_has_three_views_an_outline_and_a_colour_bar(tmp_path):
    anatomy, tmap = mni_inputs(tmp_path)
    outlined = intermix.glass_brain(tmap, 3, anatomy=anatomy, colorbar=False, annotate=False)
    bare = intermix.glass_brain(tmap, 3, colorbar=False, annotate=False)
    barred = intermix.glass_brain(tmap, 3, anatomy=anatomy)
    rgb = outlined.to_uint8()[..., :3].astype(int)
    outline = (np.abs(rgb - 89).max(-1) < 2)  # the outline's display grey, 0.35
    assert outline.sum() > 500
    assert not (np.abs(bare.to_uint8()[..., :3].astype(int) - 89).max(-1) < 2).any()
    assert barred.shape[1] > outlined.shape[1]
    assert (rgb[..., 0] > 200).any() and (rgb[..., 2] < 60).any(), "hot where the map shows"


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
        scene.render(colorbar=1)
    with pytest.raises(ValueError, match="colorbar 'yes' is not one of top-right"):
        scene.render(colorbar="yes")
