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
    # Python's words, not the CLI's: the message names scene.set, never --set.
    with pytest.raises(ValueError, match=r"scene\.set\('objects\.pett\.x'\): objects has no element named 'pett' \(did you mean 'pet'\?\)") as e:
        scene.set("objects.pett.x", 1)
    assert "--set" not in str(e.value)
    with pytest.raises(ValueError, match=r"scene\.set\('a=b'\): a key path has no '='"):
        scene.set("a=b", 1)


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
    scene = intermix.Scene.from_dict(volume_scene(intermix.Volume(blob_volume(), axes="kji")))
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
    with pytest.raises(ValueError, match="is not RGB in"):
        intermix.Mesh(np.eye(3), [[0, 1, 2]], colors=np.full((3, 3), 2.0))


def test_a_volume_is_no_mesh_source():
    v = intermix.Volume(blob_volume(), axes="kji")
    with pytest.raises(ValueError, match=r"^scene dict: objects\[0\]\.source: is a volume the program gave, not a mesh$"):
        intermix.Scene.from_dict({"objects": [{"name": "m", "type": "mesh", "source": v}]})
    m = intermix.Mesh(np.eye(3), [[0, 1, 2]])
    with pytest.raises(ValueError, match="is a mesh the program gave, not a volume"):
        intermix.Scene.from_dict(volume_scene(m))


# Issue 32: sizes are checked before any copy, memory errors are MemoryError with the budget,
# and images with NaN are refused where they would compare equal or show black.


def _rss_kib_after(code):
    """Peak RSS (KiB) of a fresh interpreter that runs `code` (which may raise)."""
    import subprocess
    import sys

    script = (
        "import resource, intermix, numpy as np\n"
        f"try:\n    {code}\nexcept Exception as e:\n    print(type(e).__name__, e)\n"
        "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)\n"
    )
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         env=os.environ, check=True).stdout.splitlines()
    return out[0], int(out[-1])


def test_a_zero_stride_view_is_refused_before_it_is_copied():
    # One byte viewed as 1 x 1 x 2**31 voxels: refused by its shape, never copied (2 GiB).
    code = ("intermix.Volume(np.lib.stride_tricks.as_strided(np.zeros(1, np.uint8), "
            "shape=(1, 1, 2**31), strides=(0, 0, 0)), axes=\"kji\")")
    message, peak = _rss_kib_after(code)
    assert message.startswith("ValueError Volume: shape (1, 1, 2147483648)"), message
    assert "more than 2147483648" in message or "each axis needs 1 to 2147483647" in message
    assert peak < 512 * 1024, f"peak RSS {peak} KiB"


def test_a_view_larger_than_the_budget_is_a_memory_error_naming_it():
    big = np.broadcast_to(np.float64(1.0), (1024, 1024, 512))  # 2 GiB as float32, 8 bytes here
    before = intermix.max_memory()
    intermix.set_max_memory(1 << 30)
    try:
        with pytest.raises(MemoryError) as e:
            intermix.Volume(big, axes="kji")
    finally:
        intermix.set_max_memory(0)
    assert intermix.max_memory() == before
    assert str(e.value).startswith(
        "Volume: a float32 copy of the float64 array of shape (1024, 1024, 512) needs 2.0 GiB, "
        "more than the memory budget of 1.0 GiB"), str(e.value)
    with pytest.raises(ValueError, match="set_max_memory: bytes is -1"):
        intermix.set_max_memory(-1)
    with pytest.raises(TypeError, match="set_max_memory: bytes must be an int, got str"):
        intermix.set_max_memory("1G")


def test_images_with_nan_are_refused_by_name():
    nan = np.zeros((4, 4, 4), np.float32)
    nan[1, 2, 0] = np.nan
    nan[0, 0, 3] = np.inf
    zeros = np.zeros((4, 4, 4), np.float32)
    with pytest.raises(ValueError, match=r"compare: a: 2 of the image's 64 values are NaN or infinite"):
        intermix.compare(nan, zeros)
    with pytest.raises(ValueError, match=r"to_uint8: 2 of the image's 64 values"):
        intermix.to_uint8(nan)
    with pytest.raises(ValueError, match=r"write_png: 2 of the image's 64 values"):
        intermix.write_png(nan, "never.png")
    assert not os.path.exists("never.png")
    all_nan = np.full((4, 4, 4), np.nan, np.float32)
    with pytest.raises(ValueError, match=r"compare: a: 64 of the image's 64 values"):
        intermix.compare(all_nan, zeros)


def test_writers_refuse_to_replace_an_input(tmp_path):
    """An output naming a file this process read (by any link to it) is refused, the file kept."""
    path = tmp_path / "v.nrrd"
    volume = intermix.Volume(blob_volume(), np.eye(4), axes="kji")
    intermix.write_volume(volume, path)
    intermix.read_volume(path)
    before = path.read_bytes()
    link = tmp_path / "link.nrrd"
    link.symlink_to(path.name)
    for target in (path, link):
        with pytest.raises(FileExistsError) as e:
            intermix.write_volume(volume, target)
        assert str(e.value) == (
            f"{target}: is an input of this command ({path}); choose another output")
    with pytest.raises(FileExistsError, match="is an input of this command"):
        intermix.write_png(np.zeros((4, 4, 4), np.float32), path)
    assert path.read_bytes() == before
    intermix.write_volume(volume, tmp_path / "copy.nrrd")  # any other name is written
