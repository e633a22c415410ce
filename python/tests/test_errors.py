"""Each error class raises the right exception with the library's message; none crashes."""

import json
import os

import numpy as np
import pytest

import intermix
from conftest import blob_volume, volume_scene


def test_missing_scene_file(tmp_path):
    path = tmp_path / "missing.json"
    with pytest.raises(FileNotFoundError) as e:
        intermix.Scene.from_file(path)
    assert str(e.value) == f"{path}: no such file"
    assert e.value.errno == 2


def test_scene_file_that_is_a_folder(tmp_path):
    with pytest.raises(IsADirectoryError) as e:
        intermix.Scene.from_file(tmp_path)
    assert str(e.value) == f"{tmp_path}: is a directory, not a file"


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads any file")
def test_unreadable_scene_file(tmp_path):
    path = tmp_path / "locked.json"
    path.write_text("{}")
    path.chmod(0)
    with pytest.raises(PermissionError, match="cannot open the file"):
        intermix.Scene.from_file(path)


def test_file_named_by_a_scene_is_missing(tmp_path):
    d = volume_scene({"file": "nope.nrrd"})
    with pytest.raises(FileNotFoundError) as e:
        intermix.Scene.from_dict(d, base_dir=tmp_path)
    assert str(e.value) == f"scene dict: objects[0].source.file: no such file '{tmp_path}/nope.nrrd'"
    (tmp_path / "s.json").write_text(json.dumps(d))
    with pytest.raises(FileNotFoundError) as e:
        intermix.Scene.from_file(tmp_path / "s.json")
    assert str(e.value) == f"{tmp_path}/s.json: objects[0].source.file: no such file '{tmp_path}/nope.nrrd'"


def test_bad_scene_values_have_the_files_messages_and_paths(tmp_path):
    d = {"objects": [], "camera": {"fov_deg": 500}}
    (tmp_path / "s.json").write_text(json.dumps(d))
    with pytest.raises(ValueError) as from_file:
        intermix.Scene.from_file(tmp_path / "s.json")
    with pytest.raises(ValueError) as from_dict:
        intermix.Scene.from_dict(d)
    assert str(from_file.value) == f"{tmp_path}/s.json: camera.fov_deg: 500 is not in (0, 180)"
    assert str(from_dict.value) == "scene dict: camera.fov_deg: 500 is not in (0, 180)"
    with pytest.raises(ValueError, match=r"^scene dict: objects\[0\]\.transfer_functon: unknown key \(did you mean 'transfer_function'\?\)$"):
        intermix.Scene.from_dict({"objects": [{"name": "a", "type": "volume",
                                               "source": {"phantom": "cube"}, "transfer_functon": {}}]})


def test_invalid_json_text_and_set_paths(examples):
    with pytest.raises(ValueError, match="scene text: invalid JSON"):
        intermix.Scene.from_json("{")
    scene = intermix.Scene.from_file(os.path.join(examples, "fusion.json"))
    with pytest.raises(ValueError, match=r"--set objects\.pett\.x=1: objects has no element named 'pett' \(did you mean 'pet'\?\)"):
        scene.set("objects.pett.x", 1)


def test_file_content_that_is_wrong(tmp_path):
    path = tmp_path / "garbage.nrrd"
    path.write_bytes(b"not a nrrd file\n")
    with pytest.raises(ValueError, match=str(path)):
        intermix.read_volume(path)
    with pytest.raises(FileNotFoundError, match="no such file"):
        intermix.read_volume(tmp_path / "none.nii.gz")
    with pytest.raises(FileNotFoundError, match="no such file"):
        intermix.read_mesh(tmp_path / "none.stl")
    (tmp_path / "bad.obj").write_text("v 0 0 0\nf 1 2 3\n")
    with pytest.raises(ValueError, match="bad.obj"):
        intermix.read_mesh(tmp_path / "bad.obj")


def test_render_arguments_and_failures():
    scene = intermix.Scene.from_dict(volume_scene(intermix.Volume(blob_volume())))
    with pytest.raises(ValueError, match="method 'nope' is not available; this build has: reference"):
        scene.render(method="nope")
    with pytest.raises(ValueError, match="spp 3 is not a perfect square"):
        scene.render(spp=3)
    with pytest.raises(ValueError, match=r"width 0 is not in \[1, 16384\]"):
        scene.render(width=0)
    csg = {
        "objects": [
            {"name": "a", "type": "mesh", "source": {"primitive": "sphere", "radius": 10}},
            {"name": "b", "type": "mesh", "source": {"primitive": "box", "size": 12}},
        ],
        "csg": {"op": "difference", "a": "a", "b": "b"},
    }
    with pytest.raises(RuntimeError, match="method 'mdvr' does not render CSG"):
        intermix.Scene.from_dict(csg).render(method="mdvr", width=8, height=8)
    intermix.Scene.from_dict(csg).render(width=8, height=8)  # csg, its own method


def test_image_errors(tmp_path):
    a = np.zeros((4, 4, 4), np.float32)
    with pytest.raises(ValueError, match="sizes differ|size"):
        intermix.compare(a, np.zeros((4, 5, 4), np.float32))
    with pytest.raises(ValueError, match=r"expected an \(H, W, 4\) array"):
        intermix.to_uint8(np.zeros((4, 4), np.float32))
    with pytest.raises(TypeError, match="not linear"):
        intermix.write_png(np.zeros((4, 4, 4), np.uint8), tmp_path / "x.png")
    with pytest.raises(FileNotFoundError):
        intermix.write_png(a, tmp_path / "no" / "such" / "folder.png")


def test_mesh_errors():
    with pytest.raises(ValueError, match=r"triangle 0 uses vertex 5, but there are 3 vertices"):
        intermix.Mesh(np.zeros((3, 3)), [[0, 1, 5]])
    with pytest.raises(ValueError, match=r"vertices must have shape \(N, 3\)"):
        intermix.Mesh(np.zeros((3, 2)), [[0, 1, 2]])
    with pytest.raises(ValueError, match="not a finite position"):
        intermix.Mesh([[0, 0, 0], [1, 0, 0], [0, np.inf, 0]], [[0, 1, 2]])
    with pytest.raises(ValueError, match="not linear RGB"):
        intermix.Mesh(np.eye(3), [[0, 1, 2]], colors=np.full((3, 3), 2.0))
