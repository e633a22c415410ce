"""Volumes from numpy: the same image as the same voxels from a file, zero-copy, axis order."""

import gc
import os

import numpy as np
import pytest

import intermix
from conftest import blob_volume, oblique_affine, rss_bytes, volume_scene, write_raw_nrrd

ZERO_COPY = intermix._intermix._zero_copy


def render(scene_dict, **kw):
    return intermix.Scene.from_dict(scene_dict).render(method="mdvr", **kw)


@pytest.mark.parametrize("dtype", [np.int16, np.uint16, np.uint8, np.float32])
def test_numpy_volume_renders_as_nrrd_file(tmp_path, dtype):
    voxels = blob_volume(dtype=np.float32)
    if dtype in (np.uint16, np.uint8):
        voxels = (voxels + 1000) / (2000 if dtype == np.uint8 else 1)
    voxels = voxels.astype(dtype)
    affine = oblique_affine()
    path = tmp_path / "blob.nrrd"
    write_raw_nrrd(path, voxels, affine)
    tf = {"points": [[float(voxels.min()), 0, 0, 0, 0], [float(voxels.max()), 1, 0.9, 0.8, 0.8]]}
    from_file = volume_scene({"file": str(path)})
    from_numpy = volume_scene(intermix.Volume(voxels, affine, axes="kji"))
    for s in (from_file, from_numpy):
        s["objects"][0]["transfer_function"] = tf
    a = render(from_file)
    b = render(from_numpy)
    assert a.shape == (40, 48, 4) and a.dtype == np.float32
    assert a.max() > 0.05, "the volume shows"
    assert np.array_equal(a, b), "byte-identical to the same voxels read from NRRD"


def test_numpy_volume_renders_as_written_nrrd_with_reference(tmp_path):
    voxels = blob_volume()
    volume = intermix.Volume(voxels, oblique_affine(), axes="kji")
    intermix.write_volume(volume, tmp_path / "v.nrrd")
    a = intermix.Scene.from_dict(volume_scene({"file": str(tmp_path / "v.nrrd")})).render(
        method="reference", spp=1, width=24, height=20)
    b = intermix.Scene.from_dict(volume_scene(volume)).render(
        method="reference", spp=1, width=24, height=20)
    assert np.array_equal(a, b)


def test_nibabel_order_f_contiguous_is_the_same_volume(tmp_path):
    kji = blob_volume()
    ijk = kji.T  # (ni, nj, nk), F-contiguous: nibabel's get_fdata() order
    assert ijk.flags.f_contiguous and not ijk.flags.c_contiguous
    affine = oblique_affine()
    c = intermix.Volume(kji, affine, axes="kji")
    f = intermix.Volume(ijk, affine)
    assert c.shape == f.shape == (kji.shape[2], kji.shape[1], kji.shape[0])
    assert np.array_equal(render(volume_scene(c)), render(volume_scene(f)))
    # A C-contiguous (i, j, k) array says so, and is reordered (copied) once.
    explicit = intermix.Volume(np.ascontiguousarray(ijk), affine, axes="ijk")
    assert not explicit.shares_memory
    assert np.array_equal(render(volume_scene(c)), render(volume_scene(explicit)))


def test_ras_affine_is_lps_with_x_and_y_negated():
    voxels = blob_volume()
    lps = oblique_affine()
    ras = np.diag([-1.0, -1.0, 1.0, 1.0]) @ lps
    a = intermix.Volume(voxels, lps, axes="kji")
    b = intermix.Volume(voxels, ras, space="RAS", axes="kji")
    assert np.allclose(b.lps_affine, lps) and np.allclose(b.affine, ras)
    assert np.array_equal(render(volume_scene(a)), render(volume_scene(b)))


def test_read_volume_round_trip(tmp_path):
    voxels = blob_volume()
    affine = oblique_affine()
    intermix.write_volume(intermix.Volume(voxels, affine, axes="kji"), tmp_path / "v.nii.gz")
    array, read_affine = intermix.read_volume(tmp_path / "v.nii.gz")
    assert array.shape == voxels.shape and array.dtype == np.int16
    assert np.array_equal(array, voxels)
    assert np.allclose(read_affine, affine, atol=1e-4)
    array_ras, affine_ras = intermix.read_volume(tmp_path / "v.nii.gz", space="RAS")
    assert np.allclose(affine_ras, np.diag([-1.0, -1.0, 1.0, 1.0]) @ read_affine)
    # The array read is used again without a copy.
    again = intermix.Volume(array, read_affine, axes="kji")
    assert again.shares_memory == ZERO_COPY


@pytest.mark.parametrize(
    "dtype,stored",
    [
        (np.int8, np.int16),
        (np.bool_, np.uint8),
        (np.int32, np.int16),
        (np.int64, np.int16),
        (np.uint32, np.int16),
        (np.float64, np.float32),
        (np.float16, np.float32),
    ],
)
def test_other_dtypes_are_converted_once(dtype, stored):
    values = (blob_volume() > 0) if dtype == np.bool_ else blob_volume() // 10 + 200
    given = values.astype(dtype)
    v = intermix.Volume(given, np.eye(4), axes="kji")
    assert v.dtype == np.dtype(stored)
    assert not v.shares_memory
    assert np.array_equal(v.voxels, given.astype(stored))


def test_wide_integers_keep_their_values():
    assert intermix.Volume(np.full((2, 2, 2), 40000, np.int32), axes="kji").dtype == np.uint16
    assert intermix.Volume(np.full((2, 2, 2), 70000, np.int32), axes="kji").dtype == np.float32
    assert intermix.Volume(np.full((2, 2, 2), -5, np.int64), axes="kji").dtype == np.int16


def test_non_contiguous_arrays_are_copied_once():
    base = blob_volume()
    sliced = base[:, ::2, :]
    v = intermix.Volume(sliced, np.eye(4), axes="kji")
    assert not v.shares_memory and v.voxels.flags.c_contiguous
    assert np.array_equal(v.voxels, sliced)
    big_endian = base.astype(">i2")
    v = intermix.Volume(big_endian, np.eye(4), axes="kji")
    assert v.dtype == np.int16 and np.array_equal(v.voxels, base)


@pytest.mark.skipif(not ZERO_COPY, reason="this build copies voxels (no VoxelBuffer yet)")
@pytest.mark.parametrize("dtype", [np.uint8, np.int16, np.uint16, np.float32])
def test_engine_reads_the_arrays_own_memory(dtype):
    array = blob_volume().astype(dtype)
    v = intermix.Volume(array, np.eye(4), axes="kji")
    assert v.shares_memory
    assert v._data_address == array.ctypes.data
    ijk = array.T
    f = intermix.Volume(ijk, np.eye(4))
    assert f.shares_memory and f._data_address == array.ctypes.data


@pytest.mark.skipif(not ZERO_COPY, reason="this build copies voxels (no VoxelBuffer yet)")
def test_zero_copy_adds_no_second_copy_of_a_256_cubed_volume():
    array = np.zeros((256, 256, 256), np.uint16)
    array[64:192, 64:192, 64:192] = 1000  # touched: the array is resident
    size = array.nbytes  # 32 MiB
    gc.collect()
    before = rss_bytes()
    volume = intermix.Volume(array, np.eye(4), axes="kji")
    scene = intermix.Scene.from_dict(volume_scene(volume))
    grown = rss_bytes() - before
    assert volume._data_address == array.ctypes.data
    assert grown < size / 4, f"RSS grew by {grown / 2**20:.1f} MiB for a {size / 2**20:.0f} MiB volume"
    del scene, volume


def test_the_volume_keeps_its_array_alive():
    array = blob_volume()
    expected = array.copy()
    v = intermix.Volume(array, np.eye(4), axes="kji")
    scene = intermix.Scene.from_dict(volume_scene(v))
    del array, v
    gc.collect()
    again = intermix.Scene.from_dict(volume_scene(intermix.Volume(expected, np.eye(4), axes="kji")))
    assert np.array_equal(scene.render(method="mdvr"), again.render(method="mdvr"))


def test_phantom_and_volume_properties():
    ct = intermix.phantom("ct-head", 64)
    assert ct.dtype == np.int16 and len(ct.shape) == 3
    assert ct.voxels.shape == ct.shape[::-1]
    lo, hi = ct.range
    assert lo <= -900 and hi >= 700
    assert "ct-head" in intermix.phantom_names()
    assert "Volume" in repr(ct)


def test_volume_errors():
    with pytest.raises(ValueError, match="expected a 3-D array"):
        intermix.Volume(np.zeros((4, 4)), axes="kji")
    with pytest.raises(ValueError, match="4x4"):
        intermix.Volume(np.zeros((4, 4, 4)), np.eye(3), axes="kji")
    with pytest.raises(ValueError, match="last row"):
        intermix.Volume(np.zeros((4, 4, 4)), np.ones((4, 4)), axes="kji")
    # NaN and inf voxels are no data (a statistical map's outside), not an error.
    masked = np.ones((4, 4, 4), np.float32)
    masked[1, 2, 3] = np.nan
    masked[0, 0, 0] = -np.inf
    assert intermix.Volume(masked, axes="kji").range == (1.0, 1.0)
    # A float64 beyond float32's range would become inf, that is no data: refused, naming it.
    huge = np.ones((4, 4, 4))
    huge[1, 2, 3] = 1e300
    huge[0, 0, 0] = np.inf  # given as inf: still no data
    with pytest.warns(UserWarning, match="float64"):
        with pytest.raises(ValueError, match=r"1e\+300 at voxel \(i, j, k\) = \(3, 2, 1\)"):
            intermix.Volume(huge, axes="kji")
    given_inf = np.ones((4, 4, 4))
    given_inf[0, 0, 0] = np.inf
    with pytest.warns(UserWarning, match="float64"):
        assert intermix.Volume(given_inf, axes="kji").range == (1.0, 1.0)
    with pytest.raises(ValueError, match="singular"):
        intermix.Volume(np.zeros((4, 4, 4)), np.diag([1.0, 0.0, 1.0, 1.0]), axes="kji")
    with pytest.raises(TypeError, match="not supported"):
        intermix.Volume(np.zeros((4, 4, 4), np.complex64), axes="kji")
    with pytest.raises(ValueError, match="space 'XYZ'"):
        intermix.Volume(np.zeros((4, 4, 4)), space="XYZ")


SHARED = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                      "..", "shared", "data")


@pytest.mark.skipif(not os.path.isdir(os.path.join(SHARED, "dicom", "ct-philips")),
                    reason="no ../shared/data")
def test_dicom_and_mesh_files_as_the_scene_reads_them():
    folder = os.path.join(SHARED, "dicom", "ct-philips")
    array, affine = intermix.read_volume(folder)
    assert array.dtype == np.int16 and array.ndim == 3
    scene_file = intermix.Scene.from_dict(volume_scene({"file": folder}))
    scene_numpy = intermix.Scene.from_dict(volume_scene(intermix.Volume(array, affine, axes="kji")))
    assert np.array_equal(scene_file.render(method="mdvr"), scene_numpy.render(method="mdvr"))
    assert any("series" in note for note in scene_file.notes) or scene_file.notes == []
    with pytest.raises(ValueError, match="only DICOM sources"):
        intermix.read_volume(os.path.join(SHARED, "FLAIR.nii.gz"), series=2)
    bunny = intermix.read_mesh(os.path.join(SHARED, "bunny.ply"))
    assert bunny.vertices.shape[1] == 3 and bunny.triangles.shape[1] == 3
    assert bunny.normals is not None and not bunny.vertices.flags.writeable


def test_frames_of_a_4d_file_and_a_4d_array(tmp_path):
    """read_volume(frame=) and read_volume_info on a 4-D NIfTI written by nibabel; Volume squeezes
    a trailing axis of one frame and refuses several."""
    nib = pytest.importorskip("nibabel")
    data = np.stack([np.full((4, 5, 6), 10 * f, dtype=np.int16) for f in range(3)], axis=-1)
    data[1, 2, 3, :] = [1, 2, 3]
    img = nib.Nifti1Image(data, np.diag([2.0, 2.0, 3.0, 1.0]))
    img.header.set_xyzt_units("mm", "sec")
    img.header["pixdim"][4] = 2.5
    path = tmp_path / "four.nii.gz"
    nib.save(img, str(path))
    info = intermix.read_volume_info(path)
    assert info["frames"] == 3 and info["shape"] == (6, 5, 4)
    assert [l.get("time_s") for l in info["frame_labels"]] == [0.0, 2.5, 5.0]
    array, affine = intermix.read_volume(path, frame=2)
    assert array.shape == (6, 5, 4)
    assert array[3, 2, 1] == 3 and array[0, 0, 0] == 20
    with pytest.raises(ValueError, match="frame 3"):
        intermix.read_volume(path, frame=3)
    one = intermix.Volume(np.asfortranarray(data[..., 1:2]), np.diag([2.0, 2.0, 3.0, 1.0]),
                          space="RAS")
    assert "4x5x6" in repr(one)
    with pytest.warns(UserWarning, match=r"frame 0 of 3 .*frame=K"):
        first = intermix.Volume(np.asfortranarray(data), space="RAS")
    assert np.array_equal(first.voxels, data[..., 0].T)
    third = intermix.Volume(data, space="RAS", frame=2)
    assert np.array_equal(third.voxels, data[..., 2].T)
    with pytest.raises(ValueError, match="frame 3 asked for, but the array holds 3 frames"):
        intermix.Volume(data, space="RAS", frame=3)
