"""Movies from Python (issue 46): orbit(..., path="x.mp4") and write_movie go through the same
encoder as `intermix render --orbit`; the frames, decoded back by read_movie (FFmpeg's
libraries), are the renders (35 dB PSNR for H.264 and VP9, equal for lossless FFV1)."""

import os

import numpy as np
import pytest

import intermix


def small_scene():
    return intermix.Scene.from_dict({
        "camera": {"eye": [0, -500, 0], "target": [0, 0, 0], "up": [0, 0, 1]},
        "image": {"width": 96, "height": 64},
        "objects": [{"name": "ct", "type": "volume", "source": {"phantom": "ct-head", "size": 40},
                     "transfer_function": {"preset": "ct-bone"}}]})


def psnr(a, b):
    mse = np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2)
    return np.inf if mse == 0 else 10 * np.log10(255.0**2 / mse)


@pytest.mark.parametrize("name,codec", [("spin.mp4", "h264"), ("spin.webm", "vp9"),
                                        ("spin.mkv", "ffv1")])
def test_orbit_writes_a_movie_of_its_frames(tmp_path, capsys, name, codec):
    images = intermix.orbit(small_scene(), frames=4, path=tmp_path / name, frame_ms=100)
    assert "4/4" in capsys.readouterr().err
    movie = intermix.read_movie(tmp_path / name)
    assert movie["codec"] == codec
    assert movie["fps"] == pytest.approx(10.0)
    assert movie["frames"].shape == (4, 64, 96, 3)
    for n, image in enumerate(images):
        expected = image.to_uint8()[..., :3]
        if codec == "ffv1":
            assert np.array_equal(movie["frames"][n], expected), n
        else:
            assert psnr(movie["frames"][n], expected) >= 35.0, (n, psnr(movie["frames"][n], expected))
    assert psnr(movie["frames"][1], images[0].to_uint8()[..., :3]) < 30.0, "the orbit turns"


def test_write_movie_refuses_clearly_and_leaves_nothing(tmp_path):
    image = small_scene().render(method="mdvr")
    odd = np.zeros((31, 48, 4), np.float32)
    with pytest.raises(ValueError, match=r"odd.mp4: H.264 \(yuv420p\) needs an even width and "
                                         r"height, not 48x31"):
        intermix.write_movie([odd], tmp_path / "odd.mp4")
    with pytest.raises(ValueError, match="x.avi: not a movie name; give .mp4"):
        intermix.write_movie([image], tmp_path / "x.avi")
    with pytest.raises(ValueError, match="a movie needs at least one frame"):
        intermix.write_movie([], tmp_path / "none.mp4")
    with pytest.raises(ValueError, match=r"images\[1\]: expected an \(H, W, 4\) array"):
        intermix.write_movie([image, np.zeros((4, 4))], tmp_path / "bad.mp4")
    with pytest.raises(ValueError, match=r"write_movie: frame 1 is 16x16, the movie 48x32|"
                                         r"frame 1 is 16x16"):
        intermix.write_movie([image, np.zeros((16, 16, 4), np.float32)], tmp_path / "size.mp4")
    with pytest.raises(TypeError, match="write_movie: images must be a sequence of images"):
        intermix.write_movie(image.sum(), tmp_path / "n.mp4")
    with pytest.raises(ValueError, match=r"orbit: path '.*spin.mp4': H.264|spin.mp4: H.264"):
        scene = small_scene()
        scene.set("image.width", 47)
        intermix.orbit(scene, frames=3, path=tmp_path / "spin.mp4", progress=False)
    assert os.listdir(tmp_path) == []
    intermix.write_movie([image, image], tmp_path / "ok.mkv", fps=30)
    assert intermix.read_movie(tmp_path / "ok.mkv")["fps"] == 30


def test_read_movie_names_a_missing_or_unreadable_file_as_every_reader_does(tmp_path):
    # The guarded open before libavformat: an OSError with intermix's words, not FFmpeg's.
    with pytest.raises(FileNotFoundError, match=r"missing.mp4: no such file"):
        intermix.read_movie(tmp_path / "missing.mp4")
    with pytest.raises(IsADirectoryError, match="is a directory"):
        intermix.read_movie(tmp_path)
