"""Issue 37: nibabel images and arrays as nibabel users have them; no silent transposition."""

import os
import re
import time
import warnings

import numpy as np
import pytest

import intermix
from conftest import ROOT, rss_bytes

nib = pytest.importorskip("nibabel")

SHARED = os.path.join(ROOT, "..", "shared", "data")
FLAIR = os.path.join(SHARED, "FLAIR.nii.gz")
LPS_FROM_RAS = np.diag([-1.0, -1.0, 1.0, 1.0])


def tf_over(lo, hi):
    return {"points": [[float(lo), 0, 0, 0, 0], [float(hi), 1, 0.9, 0.8, 0.8]]}


def render(source, tf, view="left", size=48):
    return intermix.Scene.from_dict({
        "camera": {"view": view},
        "image": {"width": size, "height": size},
        "objects": [{"name": "v", "type": "volume", "source": source, "transfer_function": tf}],
    }).render(method="mdvr")


def ijk_blob(shape=(30, 38, 46)):
    """An asymmetric int16 blob in nibabel's (i, j, k) order, F-contiguous as nibabel gives it."""
    i, j, k = np.meshgrid(*[np.linspace(-1, 1, n) for n in shape], indexing="ij")
    r = np.sqrt((i - 0.2) ** 2 + (j + 0.1) ** 2 + (k * 0.8) ** 2)
    values = np.where(r < 0.6, 800.0 + 300.0 * i, 0.0) + np.where(np.abs(i - 0.6) < 0.1, 500.0, 0)
    return np.asfortranarray(values.astype(np.int16))


RAS_AFFINE = np.array([[-1.2, 0.1, 0, 20.0], [0.05, 1.1, 0, -30.0], [0, 0, 1.5, -25.0],
                       [0, 0, 0, 1]])


@pytest.mark.skipif(not os.path.exists(FLAIR), reason="no ../shared/data/FLAIR.nii.gz")
def test_flair_image_dataobj_and_float32_render_as_the_file():
    img = nib.load(FLAIR)
    tf = tf_over(0, 255)
    expected = render({"file": FLAIR}, tf)
    assert expected[..., 3].max() > 0.3, "the brain shows"
    by_image = intermix.Volume(img)
    assert by_image.shares_memory and by_image.dtype == np.uint8  # the file's own type, no copy
    as_given = [
        by_image,
        intermix.Volume(img.dataobj, img.affine, space="RAS"),
        intermix.Volume(img.get_fdata(dtype=np.float32), img.affine, space="RAS"),
    ]
    for volume in as_given:
        assert np.array_equal(render(volume, tf), expected), volume
    # The image taken as (k, j, i) would be another picture: the test can fail.
    wrong = intermix.Volume(np.asarray(img.dataobj), img.affine, space="RAS", axes="kji")
    assert not np.array_equal(render(wrong, tf), expected)


def test_scaled_and_4d_nibabel_files(tmp_path):
    data = ijk_blob()
    img = nib.Nifti1Image(data, RAS_AFFINE)
    img.header.set_slope_inter(0.5, -100.0)  # stored int16, values data * 0.5 - 100
    path = tmp_path / "scaled.nii.gz"
    nib.save(img, str(path))
    loaded = nib.load(str(path))
    volume = intermix.Volume(loaded)
    assert volume.dtype == np.float32
    assert np.allclose(volume.voxels, (np.asarray(loaded.dataobj, np.float64)).T, atol=1e-4)
    tf = tf_over(-100, 400)
    expected = render({"file": str(path)}, tf)
    assert np.array_equal(render(volume, tf), expected)
    assert np.array_equal(render(intermix.Volume(loaded.dataobj, loaded.affine, space="RAS"), tf),
                          expected)

    frames = np.stack([data, data // 2, data // 3], axis=-1)
    four = tmp_path / "four.nii.gz"
    nib.save(nib.Nifti1Image(frames, RAS_AFFINE), str(four))
    loaded = nib.load(str(four))
    with pytest.warns(UserWarning, match="frame 0 of 3"):
        first = intermix.Volume(loaded)
    assert np.array_equal(render(first, tf), render({"file": str(four)}, tf))
    second = intermix.Volume(loaded, frame=2)
    assert np.array_equal(render(second, tf), render({"file": str(four), "frame": 2}, tf))
    # A trailing axis of one voxel is dropped, as the readers drop it.
    single = nib.Nifti1Image(data[..., None, None], RAS_AFFINE)
    assert intermix.Volume(single).shape == data.shape
    with pytest.raises(ValueError, match="gives no affine|its own affine"):
        intermix.Volume(loaded, RAS_AFFINE)


def test_an_object_like_a_nibabel_image_is_taken():
    class Like:
        def __init__(self, data, affine):
            self._data, self.affine = data, affine

        def get_fdata(self, dtype=np.float64):
            return self._data.astype(dtype)

    data = ijk_blob()
    volume = intermix.Volume(Like(data, RAS_AFFINE))
    assert volume.dtype == np.float32 and volume.shape == data.shape
    assert np.allclose(volume.affine, RAS_AFFINE)


LAYOUTS = {
    "arr.copy()": lambda a: a.copy(),
    "np.ascontiguousarray(arr)": np.ascontiguousarray,
    "arr[::-1]": lambda a: a[::-1],
    "arr[::2, ::2, ::2]": lambda a: a[::2, ::2, ::2],
    "a frame of a C-ordered 4-D stack": lambda a: np.ascontiguousarray(
        np.stack([a, a // 2], axis=-1))[..., 0],
}


@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_every_layout_renders_as_its_file_or_is_refused_naming_axes(tmp_path, layout):
    """Each layout of nibabel (i, j, k) data: refused naming axes when the affine is LPS and the
    order is not given; identical to the same array written by nibabel when given in RAS; and
    (the check can fail) the transposed reading is another image."""
    arr = LAYOUTS[layout](ijk_blob())
    assert arr.flags.f_contiguous is False  # none says its order by its layout
    path = tmp_path / "layout.nii.gz"
    nib.save(nib.Nifti1Image(np.asarray(arr), RAS_AFFINE), str(path))
    affine = nib.load(str(path)).affine  # as stored: float32
    tf = tf_over(0, 1200)
    expected = render({"file": str(path)}, tf)
    assert expected[..., 3].max() > 0.2
    with pytest.raises(ValueError, match="axes='kji'.*axes='ijk'"):
        intermix.Volume(arr, LPS_FROM_RAS @ affine)
    assert np.array_equal(render(intermix.Volume(arr, affine, space="RAS"), tf), expected)
    assert np.array_equal(
        render(intermix.Volume(arr, LPS_FROM_RAS @ affine, axes="ijk"), tf), expected)
    transposed = intermix.Volume(arr, affine, space="RAS", axes="kji")
    assert not np.array_equal(render(transposed, tf), expected)


def test_float64_warns_how_to_avoid_the_copy_and_int_is_viewed():
    data = ijk_blob()
    with pytest.warns(UserWarning, match=r"get_fdata\(dtype=np\.float32\).*dataobj"):
        v = intermix.Volume(data.astype(np.float64), RAS_AFFINE, space="RAS")
    assert v.dtype == np.float32 and not v.shares_memory
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for dtype in (np.int16, np.uint16, np.uint8, np.float32):
            given = data.astype(dtype, order="F")
            viewed = intermix.Volume(given, RAS_AFFINE, space="RAS")
            assert viewed.shares_memory and viewed._data_address == given.ctypes.data


def test_a_raw_array_as_source_is_refused_at_once():
    t1 = np.ones((256, 256, 200), np.float64)  # 100 MiB, resident
    small = {"objects": [{"name": "v", "type": "volume", "source": np.ones((2, 2, 2))}]}
    with pytest.raises(ValueError):
        intermix.Scene.from_dict(small)  # warm
    before = rss_bytes()
    start = time.perf_counter()
    with pytest.raises(ValueError, match=r"objects\[0\]\.source: a numpy array .*add_volume") as e:
        intermix.Scene.from_dict({"objects": [{"name": "t1", "type": "volume", "source": t1,
                                               "transfer_function": tf_over(0, 1)}]})
    seconds = time.perf_counter() - start
    grown = rss_bytes() - before
    assert seconds < 0.010, f"{seconds * 1000:.1f} ms"
    assert grown < 1 << 20, f"RSS grew by {grown / 2**20:.2f} MiB"
    assert "intermix.Volume" in str(e.value)


def test_set_several_paths_as_one_edit_and_a_whole_block():
    scene = intermix.Scene.from_dict({
        "camera": {"eye": [0, -500, 0], "target": [0, 0, 0], "up": [0, 0, 1]},
        "image": {"width": 32, "height": 32},
        "objects": [{"name": "v", "type": "volume", "source": {"phantom": "cube", "size": 16},
                     "transfer_function": tf_over(0, 255)}]})
    before = scene.to_dict()
    # One at a time, the first leaves up parallel to the view: refused, nothing changed.
    with pytest.raises(ValueError, match="parallel"):
        scene.set("camera.eye", [0, 0, 500])
    assert scene.to_dict() == before
    scene.set({"camera.eye": [0, 0, 500], "camera.up": [0, -1, 0]})
    assert scene.camera["eye"] == (0, 0, 500) and scene.camera["up"] == (0, -1, 0)
    scene.set("camera", {"eye": [500, 0, 0], "target": [0, 0, 0], "up": [0, 0, 1]})
    assert scene.to_dict()["camera"] == {"eye": [500, 0, 0], "target": [0, 0, 0], "up": [0, 0, 1]}
    with pytest.raises(ValueError, match="parallel"):
        scene.set({"camera.up": [1, 0, 0], "image.width": 40})
    assert scene.to_dict()["image"]["width"] == 32


DICOM = os.path.join(SHARED, "dicom", "ct-philips")


@pytest.mark.skipif(not os.path.isdir(DICOM), reason="no ../shared/data/dicom")
def test_read_volume_of_a_folder_looks_only_in_it(tmp_path):
    sub = tmp_path / "series"
    sub.mkdir()
    for name in sorted(os.listdir(DICOM)):
        os.symlink(os.path.join(DICOM, name), sub / name)
    start = time.perf_counter()
    with pytest.raises(ValueError, match=r"only subfolders \(series\).*recursive=True"):
        intermix.read_volume(tmp_path)
    assert time.perf_counter() - start < 0.5
    below, _ = intermix.read_volume(tmp_path, recursive=True)
    direct, _ = intermix.read_volume(sub)
    assert np.array_equal(below, direct)
    # A file in the folder itself is read, not the larger series below it.
    enhanced = os.path.join(SHARED, "enh.dcm")
    if os.path.exists(enhanced):
        os.symlink(enhanced, tmp_path / "enh.dcm")
        alone, _ = intermix.read_volume(enhanced)
        here, _ = intermix.read_volume(tmp_path)
        assert here.shape == alone.shape and np.array_equal(here, alone)
        assert intermix.read_volume_info(tmp_path)["shape"] == alone.shape


def test_image_slices_are_plain_arrays_and_the_version_is_cmakes():
    image = intermix.Scene.from_dict({
        "image": {"width": 8, "height": 6},
        "objects": [{"name": "v", "type": "volume", "source": {"phantom": "cube", "size": 16},
                     "transfer_function": tf_over(0, 255)}]}).render(method="mdvr")
    assert type(image[..., 0]) is np.ndarray and type(image[0]) is np.ndarray
    assert type(image[1:3]) is intermix.Image
    with open(os.path.join(ROOT, "CMakeLists.txt")) as f:
        version = re.search(r"project\(intermix VERSION ([0-9.]+)", f.read()).group(1)
    assert intermix.__version__ == version
