"""Scenes from files and dicts, --set paths, to_dict, objects added from numpy."""

import json
import os
import subprocess

import numpy as np
import pytest

import intermix
from conftest import CT_TF, blob_volume, oblique_affine, volume_scene


def test_from_file_renders_what_the_cli_renders(cli, examples, tmp_path):
    scene_file = os.path.join(examples, "fusion.json")
    out = tmp_path / "cli.png"
    subprocess.run(
        [cli, "--quiet", "render", scene_file, "-o", str(out), "--method", "mdvr",
         "--width", "64", "--height", "48", "--set", "objects.pet.transfer_function.unit_distance=2"],
        check=True, capture_output=True)
    scene = intermix.Scene.from_file(scene_file)
    scene.set("objects.pet.transfer_function.unit_distance", 2)
    image = scene.render(method="mdvr", width=64, height=48)
    assert isinstance(image, intermix.Image) and image.shape == (48, 64, 4)
    intermix.write_png(image, tmp_path / "py.png")
    assert (tmp_path / "py.png").read_bytes() == out.read_bytes()


def test_dict_and_file_are_the_same_scene(examples):
    path = os.path.join(examples, "ct-head.json")
    with open(path) as f:
        d = json.load(f)
    a = intermix.Scene.from_file(path).render(method="mdvr", width=40, height=40)
    b = intermix.Scene.from_dict(d).render(method="mdvr", width=40, height=40)
    c = intermix.Scene.from_json(json.dumps(d)).render(method="mdvr", width=40, height=40)
    assert np.array_equal(a, b) and np.array_equal(a, c)


def test_to_dict_round_trips_with_volumes_in_place():
    v = intermix.Volume(blob_volume(), oblique_affine(), axes="kji")
    scene = intermix.Scene.from_dict(volume_scene(v))
    d = scene.to_dict()
    assert d["objects"][0]["source"] is v
    assert d["image"]["width"] == 48
    again = intermix.Scene.from_dict(d)
    assert np.array_equal(scene.render(method="mdvr"), again.render(method="mdvr"))


def test_set_paths_as_the_cli(examples):
    scene = intermix.Scene.from_file(os.path.join(examples, "fusion.json"))
    scene.set("image.width", 32)
    scene.set("objects.target.material.opacity", 0.8)
    scene.set("objects[1].transfer_function.points", np.array([[0, 0, 0, 0, 0], [12, 1, 1, 1, 1]]))
    d = scene.to_dict()
    assert d["image"]["width"] == 32
    assert d["objects"][2]["material"]["opacity"] == 0.8
    assert d["objects"][1]["transfer_function"]["points"][1] == [12, 1, 1, 1, 1]
    assert scene.render(method="mdvr", height=24).shape == (24, 32, 4)
    assert scene.names == ["ct", "pet", "target"]


def test_a_failed_set_leaves_the_scene_as_it_was(examples):
    scene = intermix.Scene.from_file(os.path.join(examples, "ct-head.json"))
    before = scene.to_dict()
    with pytest.raises(ValueError, match=r"camera\.fov_deg"):
        scene.set("camera.fov_deg", 500)
    assert scene.to_dict() == before


def test_set_a_volume_source_from_numpy():
    scene = intermix.Scene.from_dict(volume_scene({"phantom": "ct-head", "size": 32}))
    v = intermix.Volume(blob_volume(), oblique_affine(), axes="kji")
    scene.set("objects.ct.source", v)
    same = intermix.Scene.from_dict(volume_scene(v))
    assert np.array_equal(scene.render(method="mdvr"), same.render(method="mdvr"))


def test_add_volume_mesh_and_plane():
    scene = intermix.Scene()
    scene.set("image", {"width": 40, "height": 32})
    scene.set("camera", {"eye": [-200, -400, 90], "target": [0, 0, 0], "up": [0, 0, 1]})
    scene.add_volume("ct", blob_volume(), oblique_affine(), axes="kji", transfer_function=CT_TF)
    scene.add_volume("pet", {"phantom": "pet", "size": 32},
                     transfer_function={"points": [[0, 0, 0, 0, 0], [12, 1, 0.5, 0, 0.5]]})
    t = np.arange(12)
    verts = np.stack([np.cos(t), np.sin(t), np.zeros(12)], axis=1) * 20
    verts = np.vstack([verts, [0, 0, 25], [0, 0, -25]])
    tris = [[i, (i + 1) % 12, 12] for i in range(12)] + [[(i + 1) % 12, i, 13] for i in range(12)]
    scene.add_mesh("gem", intermix.Mesh(verts, tris), material={"color": [0.3, 0.6, 1], "opacity": 0.5})
    scene.add_mesh("ball", {"primitive": "sphere", "radius": 10},
                   transform={"translate": [20, 0, 0]})
    scene.add_plane("axial", volume="ct", center=[0, 0, 0], normal=[0, 0, 1], window=[40, 400])
    assert scene.names == ["ct", "pet", "gem", "ball", "axial"]
    image = scene.render(method="zslab")
    assert image.shape == (32, 40, 4) and image[..., 3].max() > 0.5


def test_relative_paths_resolve_against_base_dir(tmp_path):
    intermix.write_volume(intermix.Volume(blob_volume(), oblique_affine(), axes="kji"), tmp_path / "v.nrrd")
    d = volume_scene({"file": "v.nrrd"})
    scene = intermix.Scene.from_dict(d, base_dir=tmp_path)
    assert scene.base_dir == str(tmp_path)
    cwd = os.getcwd()
    try:
        os.chdir(tmp_path)
        here = intermix.Scene.from_dict(d)
    finally:
        os.chdir(cwd)
    assert np.array_equal(scene.render(method="mdvr"), here.render(method="mdvr"))


def test_scene_values_that_are_not_json():
    with pytest.raises(ValueError, match=r"scene dict: image\.width: a set is not a scene value"):
        intermix.Scene.from_dict({"objects": [], "image": {"width": {1}}})
    with pytest.raises(ValueError, match=r"scene dict: camera\.fov_deg: nan is not a finite number"):
        intermix.Scene.from_dict({"objects": [], "camera": {"fov_deg": float("nan")}})
    with pytest.raises(ValueError, match="keys must be strings"):
        intermix.Scene.from_dict({"objects": [], 3: 4})
    nested = []
    nested.append(nested)
    with pytest.raises(ValueError, match="nested deeper"):
        intermix.Scene.from_dict({"objects": nested})


def test_repr_png_and_help():
    scene = intermix.Scene.from_dict(volume_scene({"phantom": "ct-head", "size": 32}, width=600, height=300))
    png = scene._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    image = scene.render(method="mdvr", width=20, height=10)
    assert image._repr_png_()[:4] == b"\x89PNG"
    assert type(image[..., 0]) is np.ndarray and type(image[:4]) is intermix.Image
    assert "from_file" in intermix.Scene.__doc__
    assert "GIL" in intermix.Scene.render.__doc__
    assert "<intermix.Scene scene dict: ct (volume)" in repr(scene)


def test_from_files_builds_what_render_builds(cli, tmp_path):
    """Scene.from_files is `intermix render FILE...`: the same document, the same image."""
    volume = tmp_path / "head.nrrd"
    subprocess.run([cli, "phantom", "ct-head", "--size", "40", "-o", str(volume)], check=True)
    saved = tmp_path / "built.json"
    png = tmp_path / "cli.png"
    subprocess.run([cli, "--quiet", "render", str(volume), "-o", str(png), "--width", "48",
                    "--height", "48", "--save-scene", str(saved)], check=True)
    scene = intermix.Scene.from_files([volume])
    built = json.loads(saved.read_text())
    doc = scene.to_dict()
    assert doc["objects"] == built["objects"]
    assert doc["camera"] == intermix.Scene.from_files(volume).to_dict()["camera"]
    assert any("no transfer_function" in n for n in scene.notes)
    scene.set("image.width", 48)
    scene.set("image.height", 48)
    intermix.write_png(scene.render(), tmp_path / "py.png")
    assert (tmp_path / "py.png").read_bytes() == png.read_bytes()
    left = intermix.Scene.from_files(volume, view="left").to_dict()["camera"]
    assert left["eye"] != doc["camera"]["eye"]


def test_from_files_errors_name_the_argument_or_file(tmp_path):
    with pytest.raises(TypeError, match="Scene.from_files: paths must be a path or a list"):
        intermix.Scene.from_files(3)
    with pytest.raises(OSError, match="nope.nii: no such file"):
        intermix.Scene.from_files(tmp_path / "nope.nii")
    with pytest.raises(ValueError, match="view 'up' is not one of anterior"):
        intermix.Scene.from_files(tmp_path, view="up")
    (tmp_path / "notes.txt").write_text("x")
    with pytest.raises(ValueError, match="notes.txt: '.txt' is not a format intermix reads"):
        intermix.Scene.from_files([tmp_path / "notes.txt"])


def test_measurements_are_the_annotations_in_numbers():
    # Values equal to the RAS x coordinate of 1 mm voxels; the scene in RAS, as the points are.
    k, j, i = np.meshgrid(np.arange(8), np.arange(8), np.arange(8), indexing="ij")
    v = intermix.Volume(i.astype(np.float32), np.eye(4), axes="kji", space="RAS")
    d = volume_scene(v)
    d["space"] = "RAS"
    d["annotations"] = [
        {"kind": "ruler", "points": [[0, 0, 0], [3, 4, 0]], "label": "r"},
        # A square between voxel centres 2..5 on the plane z = 3: 16 voxels, x from 2 to 5.
        {"kind": "polygon", "volume": "ct",
         "points": [[1.5, 1.5, 3], [5.5, 1.5, 3], [5.5, 5.5, 3], [1.5, 5.5, 3]]},
    ]
    m = intermix.Scene.from_dict(d).measurements
    assert [x["kind"] for x in m] == ["ruler", "polygon"]
    assert m[0]["label"] == "r" and m[0]["length_mm"] == pytest.approx(5.0)
    assert m[1]["voxels"] == 16 and m[1]["area_mm2"] == pytest.approx(16.0)
    assert m[1]["mean"] == pytest.approx(3.5) and (m[1]["min"], m[1]["max"]) == (2.0, 5.0)
    assert m[1]["sd"] == pytest.approx(np.std([2, 3, 4, 5]))
    assert intermix.Scene.from_dict(volume_scene(v)).measurements == []
