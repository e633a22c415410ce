"""Issue 44: intermix.Streamlines from files, nibabel and DIPY-style arrays; Scene.add_streamlines;
tracts_over_anatomy. Coordinates are checked against nibabel's reading (RAS mm, x and y negated
into LPS)."""

import os
import tracemalloc
import warnings

import numpy as np
import pytest

import intermix
from conftest import ROOT

NEURO = os.path.join(ROOT, "..", "shared", "data", "neuro")
TRACTS = os.path.join(NEURO, "tracts")
IFOF = os.path.join(TRACTS, "tract.IFOF_R.trk")
T1 = os.path.join(NEURO, "volumes", "avg152T1_RL_nifti.nii.gz")
LPS = np.array([-1.0, -1.0, 1.0])

needs_shared = pytest.mark.skipif(not os.path.exists(IFOF) or not os.path.exists(T1),
                                  reason="no ../shared/data/neuro (tracts and the MNI T1)")


def nibabel():
    return pytest.importorskip("nibabel")


def nib_load(path):
    """nibabel's reading of a tractogram (its header warnings are not this test's subject)."""
    nib = nibabel()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return nib.streamlines.load(path)


def random_streamlines(count=7, seed=3, dtype=np.float32):
    """A DIPY-style list of (n, 3) RAS arrays of 1 to 9 points."""
    rng = np.random.default_rng(seed)
    return [(rng.normal(size=(int(n), 3)) * 30).astype(dtype)
            for n in rng.integers(1, 10, size=count)]


def expected_offsets(lengths):
    return np.concatenate([[0], np.cumsum(lengths)]).astype(np.uint32)


# ---- files against nibabel ----

@needs_shared
@pytest.mark.parametrize("name", ["tract.IFOF_R.trk", "colby.trk", "tract.SLF1_R.tck"])
def test_file_points_are_nibabels_in_lps(name):
    path = os.path.join(TRACTS, name)
    reference = nib_load(path).streamlines
    by_file = intermix.Streamlines(path)
    assert by_file.count == len(reference) == len(by_file)
    assert np.array_equal(by_file.offsets, expected_offsets(reference._lengths))
    assert np.abs(by_file.points - np.concatenate(list(reference)) * LPS).max() < 1e-4
    assert np.abs(by_file[1] - reference[1] * LPS).max() < 1e-4
    loaded = intermix.Streamlines.load(path)
    assert np.array_equal(loaded.points, by_file.points)


@needs_shared
def test_nibabel_tractogram_equals_the_file_and_keeps_its_values():
    path = os.path.join(TRACTS, "colby.trk")
    trk = nib_load(path)
    from_nibabel = intermix.Streamlines(trk)  # a TrkFile: its tractogram
    by_file = intermix.Streamlines(path)
    assert np.array_equal(from_nibabel.offsets, by_file.offsets)
    assert np.abs(from_nibabel.points - by_file.points).max() < 1e-4
    dpp = trk.tractogram.data_per_point
    assert sorted(from_nibabel.point_values) == sorted(dpp.keys())
    for key in dpp.keys():
        got = from_nibabel.point_values[key]
        assert np.array_equal(got, dpp[key]._data[:, 0].astype(np.float32)), key
        with pytest.raises(ValueError):
            got[0] = 1  # read-only views


# ---- arrays ----

def test_dipy_list_and_numpy_offsets_flip_ras_into_lps():
    lines = random_streamlines()
    lengths = [len(line) for line in lines]
    ras = np.concatenate(lines)
    from_list = intermix.Streamlines(lines)
    assert from_list.count == len(lines)
    assert np.array_equal(from_list.offsets, expected_offsets(lengths))
    assert np.array_equal(from_list.lengths, lengths)
    assert np.array_equal(from_list.points, ras * LPS.astype(np.float32))
    from_arrays = intermix.Streamlines(ras, expected_offsets(lengths))
    assert np.array_equal(from_arrays.points, from_list.points)
    as_lps = intermix.Streamlines(ras.astype(np.float64), expected_offsets(lengths), space="LPS")
    assert np.array_equal(as_lps.points, ras)
    points = from_list.points
    assert points.dtype == np.float32 and not points.flags.writeable
    with pytest.raises(ValueError):
        points[0, 0] = 1.0
    assert np.array_equal(from_list[-1], lines[-1] * LPS.astype(np.float32))
    # A tuple and a generator of arrays read alike.
    assert np.array_equal(intermix.Streamlines(tuple(lines)).points, points)
    assert np.array_equal(intermix.Streamlines(line for line in lines).points, points)


def test_array_sequence_count_points_and_slices():
    nib = nibabel()
    lines = random_streamlines(count=9, dtype=np.float64)
    seq = nib.streamlines.ArraySequence(lines)
    s = intermix.Streamlines(seq)
    assert s.count == 9
    assert np.array_equal(s.offsets, expected_offsets(seq._lengths))
    assert np.allclose(s.points, seq._data * LPS, atol=1e-5)
    # A slice of an ArraySequence shares _data with gaps and another order.
    reversed_seq = seq[::-1]
    assert reversed_seq._data is seq._data
    r = intermix.Streamlines(reversed_seq)
    for i in range(r.count):
        assert np.allclose(r[i], lines[::-1][i] * LPS, atol=1e-5), i
    empty = intermix.Streamlines(nib.streamlines.ArraySequence())
    assert empty.count == 0 and empty.points.shape == (0, 3)


def test_tractogram_affine_values_and_columns():
    nib = nibabel()
    lines = random_streamlines(count=4)
    affine = np.array([[0, -2.0, 0, 10], [1.5, 0, 0, -4], [0, 0, 1.0, 7], [0, 0, 0, 1]])
    fa = [np.linspace(0, 1, len(line))[:, None] for line in lines]
    rgb = [np.random.default_rng(1).random((len(line), 3)) for line in lines]
    weight = np.arange(4, dtype=np.float64)[:, None] + 0.5
    t = nib.streamlines.Tractogram(lines, data_per_point={"fa": fa, "rgb": rgb},
                                   data_per_streamline={"weight": weight},
                                   affine_to_rasmm=affine)
    s = intermix.Streamlines(t)
    ras = np.concatenate(lines) @ affine[:3, :3].T + affine[:3, 3]
    assert np.abs(s.points - ras * LPS).max() < 1e-4
    assert s.value_names == ["fa", "rgb[0]", "rgb[1]", "rgb[2]", "weight"]
    assert np.allclose(s.point_values["fa"], np.concatenate(fa)[:, 0])
    assert np.allclose(s.point_values["rgb[2]"], np.concatenate(rgb)[:, 2])
    assert np.allclose(s.streamline_values["weight"], weight[:, 0])
    # Explicit values with arrays.
    plain = intermix.Streamlines(lines, point_values={"t": np.arange(len(s.points))},
                                 streamline_values={"id": [1, 2, 3, 4]})
    assert np.array_equal(plain.point_values["t"], np.arange(len(s.points)))
    assert plain.value_names == ["t", "id"]


def test_arrays_are_read_without_a_python_copy():
    nib = nibabel()
    rng = np.random.default_rng(0)
    lengths = np.full(20000, 50)
    data = rng.normal(size=(int(lengths.sum()), 3)).astype(np.float32)  # 12 MB
    for source in (nib.streamlines.ArraySequence(), data.astype(np.float64)):
        if isinstance(source, np.ndarray):
            args = (source, expected_offsets(lengths))
        else:
            source._data, source._offsets, source._lengths = data, \
                expected_offsets(lengths)[:-1].astype(np.int64), lengths.astype(np.int64)
            args = (source,)
        tracemalloc.start()
        s = intermix.Streamlines(*args)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        assert s.count == 20000 and len(s.points) == len(data)
        assert peak < 2_000_000, f"Python allocated {peak} bytes converting {type(source)}"


# ---- bad input ----

def test_bad_arrays_raise_one_clear_error():
    nib = nibabel()
    good = np.zeros((5, 3), np.float32)
    with pytest.raises(ValueError, match=r"points must have shape \(n, 3\), got \(5, 2\)"):
        intermix.Streamlines(np.zeros((5, 2)), [0, 5])
    with pytest.raises(ValueError, match=r"streamline 1 must have shape \(n, 3\), got \(4,\)"):
        intermix.Streamlines([good, np.zeros(4)])
    with pytest.raises(ValueError, match="offsets end at 9 but points has 5 rows"):
        intermix.Streamlines(good, [0, 2, 9])
    with pytest.raises(ValueError, match="offsets decrease: offsets\\[2\\] = 1 after 3"):
        intermix.Streamlines(good, [0, 3, 1, 5])
    with pytest.raises(ValueError, match="offsets must start at 0"):
        intermix.Streamlines(good, [1, 5])
    with pytest.raises(TypeError, match="offsets must be integers"):
        intermix.Streamlines(good, [0.0, 5.0])
    seq = nib.streamlines.ArraySequence([good, good])
    seq._offsets = np.array([0, 8])  # the second streamline's start lies beyond _data
    with pytest.raises(ValueError, match=r"streamline 1 lies at _data\[8:13\], outside the 10 rows"):
        intermix.Streamlines(seq)
    bad = good.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="point 1 of streamline 1 is .* not a finite position"):
        intermix.Streamlines(bad, [0, 2, 5])
    with pytest.raises(ValueError, match=r"point_values\['fa'\] has 4 rows, but there are 5 points"):
        intermix.Streamlines(good, [0, 5], point_values={"fa": np.zeros(4)})
    with pytest.raises(ValueError, match="space 'MNI' is not RAS or LPS"):
        intermix.Streamlines(good, [0, 5], space="MNI")
    with pytest.raises(TypeError, match="Streamlines: source must be"):
        intermix.Streamlines(42)
    with pytest.raises(ValueError, match="Streamlines: streamline 0 is not an array of numbers"):
        intermix.Streamlines([["a", "b", "c"]])
    t = nib.streamlines.Tractogram([good], affine_to_rasmm=np.eye(4))
    t._affine_to_rasmm = None
    with pytest.raises(ValueError, match="affine_to_rasmm is None"):
        intermix.Streamlines(t)
    with pytest.raises(FileNotFoundError):
        intermix.Streamlines("/nonexistent/tracts.trk")


# ---- scenes ----

def tract_scene():
    return intermix.Scene.from_dict({
        "camera": {"view": "left"}, "image": {"width": 48, "height": 48},
        "objects": []})


@needs_shared
def test_add_streamlines_writes_the_scene_document():
    scene = tract_scene()
    scene.add_streamlines(IFOF, radius=0.8, colouring="fixed", color=[1, 0.5, 0])
    streamlines = intermix.Streamlines(IFOF)
    scene.add_streamlines(streamlines, opacity=0.5, stride=2, name="every-second")
    scene.add_streamlines(streamlines)
    doc = scene.to_dict()["objects"]
    assert scene.names == ["tract_IFOF_R", "every-second", "streamlines"]
    assert doc[0] == {"name": "tract_IFOF_R", "type": "streamlines", "source": {"file": IFOF},
                      "radius": 0.8, "color_by": "fixed", "color": [1, 0.5, 0], "opacity": 1.0,
                      "stride": 1, "min_length": 0.0}
    assert doc[1]["source"] is streamlines and doc[1]["stride"] == 2
    assert intermix.Scene.from_dict(scene.to_dict()).names == scene.names
    with pytest.raises(ValueError, match="colouring 'rainbow' is not one of direction"):
        scene.add_streamlines(streamlines, colouring="rainbow")
    with pytest.raises(ValueError, match="no values named 'fa' \\(they have none\\)"):
        scene.add_streamlines(streamlines, value="fa")
    with pytest.raises(ValueError, match="radius"):
        scene.add_streamlines(streamlines, radius=-1)
    assert scene.names == ["tract_IFOF_R", "every-second", "streamlines"], "failed adds leave the scene"
    # The file and the same tractogram from nibabel draw the same image.
    by_file = tract_scene()
    by_file.add_streamlines(IFOF, name="t")
    by_nibabel = tract_scene()
    by_nibabel.add_streamlines(nib_load(IFOF).tractogram, name="t")
    a, b = by_file.render(method="zslab-hybrid"), by_nibabel.render(method="zslab-hybrid")
    assert a[..., 3].max() > 0.5, "the tract shows"
    assert np.abs(a - b).max() < 1e-3


@needs_shared
def test_value_colouring_is_inferred_from_the_tractogram():
    path = os.path.join(TRACTS, "colby.trk")
    s = intermix.Streamlines(path)
    if not s.point_values:
        pytest.skip("colby.trk's scalars were not read")
    name = s.value_names[0]
    scene = tract_scene()
    scene.add_streamlines(s, value=name, colormap="hot")
    assert scene.to_dict()["objects"][0]["color_by"] == "point_value"


# ---- tracts over anatomy ----

def project(points, camera, width, height):
    """Pixel (column, row) of world points through the camera (src/core/camera_model.cpp)."""
    eye, target, up = (np.asarray(camera[k], float) for k in ("eye", "target", "up"))
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    half = np.tan(np.radians(camera["fov_deg"]) / 2)
    d = points - eye
    z = d @ forward
    x = (d @ right) / z / (half * width / height)
    y = (d @ true_up) / z / half
    return (x + 1) / 2 * width, (1 - y) / 2 * height


@needs_shared
def test_tracts_over_anatomy_shows_the_tract_where_it_projects():
    size = 96
    scene = intermix.tracts_over_anatomy_scene(IFOF, T1, view="left", radius=0.8, width=size,
                                               height=size)
    assert scene.names == ["anatomy", "slice", "tracts"]
    camera = scene.camera
    scene.set("camera", camera)  # the framing fixed, so hiding the tract does not move it
    with_tract = scene.render(spp=16)  # tubes thinner than a pixel need the samples
    anatomy_only = scene.copy()
    anatomy_only.set("objects.tracts.visible", False)
    without = anatomy_only.render(spp=16)
    assert without[..., :3].max() > 0.2, "the anatomical slice shows"
    differs = np.abs(with_tract - without).max(axis=2) > 0.02
    # Every segment sampled every 1/8 of its length: where the tubes' axes project.
    s = intermix.Streamlines(IFOF)
    axis = [s[i][:-1] + t * (s[i][1:] - s[i][:-1]) for i in range(s.count)
            for t in np.linspace(0, 1, 8, endpoint=False)]
    cols, rows = project(np.concatenate(axis).astype(float), camera, size, size)
    hit = np.zeros((size, size), bool)
    hit[np.clip(rows.astype(int), 0, size - 1), np.clip(cols.astype(int), 0, size - 1)] = True
    near = hit.copy()
    for dr in (-2, -1, 0, 1, 2):
        for dc in (-2, -1, 0, 1, 2):
            near |= np.roll(np.roll(hit, dr, 0), dc, 1)
    assert differs[hit].mean() > 0.8, "the tract shows over the anatomy where it projects"
    assert not differs[~near].any(), "and nowhere else"
    # The one-liner renders that scene.
    image = intermix.tracts_over_anatomy(IFOF, T1, view="left", radius=0.8, width=size,
                                         height=size, spp=16)
    assert np.abs(image - with_tract).max() < 1e-6
    with pytest.raises(ValueError, match="view 'lateral' is not one of left"):
        intermix.tracts_over_anatomy(IFOF, T1, view="lateral")
