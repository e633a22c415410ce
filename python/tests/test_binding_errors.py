"""Issue 32: every bad argument raises TypeError, ValueError, OSError or MemoryError with
intermix's own message naming the function and the argument, never pybind11's text.

The sweep calls every public function with each bad value in each argument (a value that is
valid there just runs); python/src/arguments.* converts the arguments.
"""

import math
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import intermix

BAD_VALUES = [2**31, 2**63, 2**70, -1, -(2**31), 0, 1.5, math.nan, math.inf, "x", None, [], {},
              object(), b"abc", True, np.int64(2**40), np.float32(3), np.bool_(True)]
PYBIND11_PHRASES = ("incompatible function arguments", "incompatible constructor arguments",
                    "Unable to cast", "Invoked with", "std::", "pybind11",
                    "No constructor defined", "_intermix.", "\nAt:\n", "SystemError")
ALLOWED = (TypeError, ValueError, OSError, MemoryError)

SPHERE_SCENE = {
    "camera": {"eye": [0, -300, 0], "target": [0, 0, 0], "up": [0, 0, 1]},
    "image": {"width": 8, "height": 8},
    "render": {"method": "mdvr"},
    "objects": [{"name": "s", "type": "mesh", "source": {"primitive": "sphere", "radius": 40}}],
}
IMAGE = np.zeros((4, 4, 4), np.float32)
VOXELS = np.zeros((4, 4, 4), np.float32)
VERTICES = np.eye(3, dtype=np.float32)
TRIANGLES = np.array([[0, 1, 2]], np.uint32)
MISSING = "/nonexistent/intermix-test.nii"


def scene():
    return intermix.Scene.from_dict(SPHERE_SCENE)


def budget(value):
    try:
        intermix.set_max_memory(value)
    finally:
        intermix.set_max_memory(0)


def kept_budget(value):
    setattr(intermix.Renderer(), "kept_budget", value)


VOLUME = intermix.phantom("cube", 8)
BALL = {"primitive": "sphere", "radius": 5}

# (call, the words of which the message names one: the argument, or the JSON path it sets)
SWEEP = {
    "Scene.render(method)": (lambda v: scene().render(method=v), ["method"]),
    "Scene.render(width)": (lambda v: scene().render(width=v), ["width"]),
    "Scene.render(height)": (lambda v: scene().render(height=v), ["height"]),
    "Scene.render(spp)": (lambda v: scene().render(spp=v), ["spp"]),
    "Scene.render(threads)": (lambda v: scene().render(threads=v), ["threads"]),
    "Renderer(kept_budget)": (lambda v: intermix.Renderer(v), ["kept_budget"]),
    "Renderer.kept_budget =": (kept_budget, ["kept_budget"]),
    "Renderer.render(scene)": (lambda v: intermix.Renderer().render(v), ["scene"]),
    "Renderer.render(method)": (lambda v: intermix.Renderer().render(scene(), method=v), ["method"]),
    "Renderer.render(width)": (lambda v: intermix.Renderer().render(scene(), width=v), ["width"]),
    "Renderer.render(height)": (lambda v: intermix.Renderer().render(scene(), height=v), ["height"]),
    "Renderer.render(spp)": (lambda v: intermix.Renderer().render(scene(), spp=v), ["spp"]),
    "Renderer.render(threads)": (lambda v: intermix.Renderer().render(scene(), threads=v), ["threads"]),
    "phantom(name)": (lambda v: intermix.phantom(v, 8), ["name"]),
    "phantom(size)": (lambda v: intermix.phantom("cube", v), ["size"]),
    "default_spp(method)": (lambda v: intermix.default_spp(v), ["method"]),
    "set_max_memory(bytes)": (budget, ["bytes"]),
    "read_volume(path)": (lambda v: intermix.read_volume(v), ["path"]),
    "read_volume(space)": (lambda v: intermix.read_volume(MISSING, space=v), ["space"]),
    "read_volume(series)": (lambda v: intermix.read_volume(MISSING, series=v), ["series"]),
    "read_volume(units)": (lambda v: intermix.read_volume(MISSING, units=v), ["units"]),
    "read_volume(slice_spacing_mm)": (
        lambda v: intermix.read_volume(MISSING, slice_spacing_mm=v), ["slice_spacing_mm"]),
    "read_volume(frame)": (lambda v: intermix.read_volume(MISSING, frame=v), ["frame"]),
    "read_volume_info(path)": (lambda v: intermix.read_volume_info(v), ["path"]),
    "read_volume_info(series)": (lambda v: intermix.read_volume_info(MISSING, series=v), ["series"]),
    "read_mesh(path)": (lambda v: intermix.read_mesh(v), ["path"]),
    "read_mesh(space)": (lambda v: intermix.read_mesh("/nonexistent/m.ply", space=v), ["space"]),
    "read_mesh(crease_angle_deg)": (
        lambda v: intermix.read_mesh("/nonexistent/m.ply", crease_angle_deg=v), ["crease_angle_deg"]),
    "write_volume(volume)": (lambda v: intermix.write_volume(v, "v.nrrd"), ["volume"]),
    "write_volume(path)": (lambda v: intermix.write_volume(VOLUME, v), ["path"]),
    "write_volume(compress)": (lambda v: intermix.write_volume(VOLUME, "v.nrrd", compress=v), ["compress"]),
    "to_uint8(image)": (lambda v: intermix.to_uint8(v), ["image"]),
    "to_uint8(linear)": (lambda v: intermix.to_uint8(IMAGE, v), ["linear"]),
    "write_png(image)": (lambda v: intermix.write_png(v, "i.png"), ["image"]),
    "write_png(path)": (lambda v: intermix.write_png(IMAGE, v), ["path"]),
    "write_png(linear)": (lambda v: intermix.write_png(IMAGE, "i.png", v), ["linear"]),
    "write_movie(images)": (lambda v: intermix.write_movie(v, "m.mkv"), ["images"]),
    "write_movie(path)": (lambda v: intermix.write_movie([IMAGE], v), ["path"]),
    "write_movie(fps)": (lambda v: intermix.write_movie([IMAGE], "m.mkv", v), ["fps"]),
    "read_movie(path)": (lambda v: intermix.read_movie(v), ["path"]),
    "read_png(path)": (lambda v: intermix.read_png(v), ["path"]),
    "read_png(linear)": (lambda v: intermix.read_png("/nonexistent/i.png", v), ["linear"]),
    "encode_png(image)": (lambda v: intermix.encode_png(v), ["image"]),
    "encode_png(linear)": (lambda v: intermix.encode_png(IMAGE, v), ["linear"]),
    "compare(a)": (lambda v: intermix.compare(v, IMAGE), ["compare: a"]),
    "compare(b)": (lambda v: intermix.compare(IMAGE, v), ["compare: b"]),
    "error_heat_map(a)": (lambda v: intermix.error_heat_map(v, IMAGE), ["error_heat_map: a"]),
    "error_heat_map(b)": (lambda v: intermix.error_heat_map(IMAGE, v), ["error_heat_map: b"]),
    "error_heat_map(scale)": (lambda v: intermix.error_heat_map(IMAGE, IMAGE, v), ["scale"]),
    "Volume(array)": (lambda v: intermix.Volume(v), ["array"]),
    "Volume(affine)": (lambda v: intermix.Volume(VOXELS, v), ["affine"]),
    "Volume(space)": (lambda v: intermix.Volume(VOXELS, space=v), ["space"]),
    "Volume(axes)": (lambda v: intermix.Volume(VOXELS, axes=v), ["axes"]),
    "Mesh(vertices)": (lambda v: intermix.Mesh(v, TRIANGLES), ["vertices"]),
    "Mesh(triangles)": (lambda v: intermix.Mesh(VERTICES, v), ["triangles"]),
    "Mesh(normals)": (lambda v: intermix.Mesh(VERTICES, TRIANGLES, normals=v), ["normals"]),
    "Mesh(colors)": (lambda v: intermix.Mesh(VERTICES, TRIANGLES, colors=v), ["colors"]),
    "Mesh(space)": (lambda v: intermix.Mesh(VERTICES, TRIANGLES, space=v), ["space"]),
    "Mesh(crease_angle_deg)": (
        lambda v: intermix.Mesh(VERTICES, TRIANGLES, crease_angle_deg=v), ["crease_angle_deg"]),
    "Scene(base_dir)": (lambda v: intermix.Scene(v), ["base_dir"]),
    "Scene.from_file(path)": (lambda v: intermix.Scene.from_file(v), ["path"]),
    "Scene.from_dict(scene)": (lambda v: intermix.Scene.from_dict(v), ["scene"]),
    "Scene.from_dict(base_dir)": (lambda v: intermix.Scene.from_dict({"objects": []}, base_dir=v), ["base_dir"]),
    "Scene.from_json(text)": (lambda v: intermix.Scene.from_json(v), ["text"]),
    "Scene.from_json(base_dir)": (lambda v: intermix.Scene.from_json('{"objects": []}', base_dir=v), ["base_dir"]),
    "Scene.set(path)": (lambda v: scene().set(v, 1), ["path", "scene.set"]),
    "Scene.set(value)": (lambda v: scene().set("camera.fov_deg", v), ["camera.fov_deg"]),
    "Scene.add_volume(name)": (lambda v: scene().add_volume(v, VOLUME), ["name"]),
    "Scene.add_volume(source)": (lambda v: scene().add_volume("v", v), ["source"]),
    "Scene.add_volume(affine)": (lambda v: scene().add_volume("v", VOXELS, v), ["affine"]),
    "Scene.add_volume(space)": (lambda v: scene().add_volume("v", VOXELS, space=v), ["space"]),
    "Scene.add_volume(**style)": (lambda v: scene().add_volume("v", VOLUME, style=v), ["style"]),
    "Scene.add_mesh(name)": (lambda v: scene().add_mesh(v, BALL), ["name"]),
    "Scene.add_mesh(source)": (lambda v: scene().add_mesh("m", v), ["source"]),
    "Scene.add_mesh(**material)": (
        lambda v: scene().add_mesh("m", BALL, material=v), ["material"]),
    "Scene.add_plane(name)": (lambda v: scene().add_plane(v, center=[0, 0, 0], normal=[0, 0, 1], size=[9, 9]), ["name"]),
    "Scene.add_plane(**normal)": (lambda v: scene().add_plane("p", center=[0, 0, 0], size=[9, 9], normal=v), ["normal"]),
}


def check_message(error, words, value, label):
    message = str(error)
    assert isinstance(error, ALLOWED), f"{label}({value!r}): {type(error).__name__}: {message}"
    assert not any(p in message for p in PYBIND11_PHRASES), f"{label}({value!r}): {message}"
    if isinstance(error, OSError):
        return  # a file that cannot be read or written: the message names the file
    named = any(w in message for w in words)
    # A path the library could not use (a wrong extension), or a key path scene.set could not
    # set, is named by itself.
    named = named or (isinstance(value, str) and (f"{value}:" in message or f"'{value}'" in message))
    assert named, f"{label}({value!r}): {type(error).__name__}: {message!r} names none of {words}"


def test_every_bad_argument_gets_intermixs_own_message(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # valid path values ("x") write here
    failures = []
    for label, (call, words) in SWEEP.items():
        for value in BAD_VALUES:
            try:
                call(value)
            except Exception as e:  # noqa: BLE001: every exception is judged
                try:
                    check_message(e, words, value, label)
                except AssertionError as failure:
                    failures.append(str(failure).split("\n")[0])
    assert intermix.max_memory() > 0
    assert not failures, f"{len(failures)} bad messages:\n" + "\n".join(failures[:40])


def public_callables():
    """Every public function and method of the package, with a name for messages."""
    for name in intermix.__all__:
        value = getattr(intermix, name)
        if name == "Image":
            continue  # pure Python
        if isinstance(value, type):
            for member in dir(value):
                if member.startswith("_") and member != "__init__":
                    continue
                attribute = getattr(value, member)
                if callable(attribute):
                    yield f"{name}.{member}", value, member
        else:
            yield name, None, name


def test_calls_that_fit_no_signature_get_intermixs_own_type_error():
    failures = []
    for label, cls, member in public_callables():
        if cls is None:
            function = getattr(intermix, member)
        elif member == "__init__":
            function = cls
        elif isinstance(cls.__dict__.get(member), staticmethod):
            function = getattr(cls, member)
        else:
            instance = scene() if cls is intermix.Scene else None
            if cls is intermix.Renderer:
                instance = intermix.Renderer()
            if instance is None:
                continue  # Volume, Mesh, RendererStats have no public methods
            function = getattr(instance, member)
        for args, kwargs in [((), {"__no_such_keyword": 1}), ((0,) * 12, {})]:
            try:
                function(*args, **kwargs)
            except Exception as e:  # noqa: BLE001
                message = str(e)
                if not isinstance(e, ALLOWED) or any(p in message for p in PYBIND11_PHRASES):
                    failures.append(f"{label}: {type(e).__name__}: {message[:120]!r}")
    assert not failures, "\n".join(failures)


def message_of(call):
    with pytest.raises(ALLOWED) as e:
        call()
    return type(e.value), str(e.value)


def test_exact_messages():
    s = scene()
    assert message_of(lambda: s.render(width=2**31)) == (
        ValueError, "Scene.render: width 2147483648 is not in [1, 16384]")
    assert message_of(lambda: s.render(width="8")) == (
        TypeError, "Scene.render: width must be an int, got str")
    assert message_of(lambda: s.render(spp=np.float32(4))) == (
        TypeError, "Scene.render: spp must be an int, got numpy.float32")
    assert message_of(lambda: intermix.Renderer().render(s, height=True)) == (
        TypeError, "Renderer.render: height must be an int, got bool")
    assert message_of(lambda: intermix.phantom("cube", 1.5)) == (
        TypeError, "phantom: size must be an int, got float")
    assert message_of(lambda: intermix.phantom("cube", 2**70)) == (
        ValueError, "phantom: size 1180591620717411303424 is not in [8, 1024]")
    assert message_of(lambda: intermix.read_volume(MISSING, frame=-1)) == (
        ValueError, "read_volume: frame -1 is not in [0, 65535]")
    assert message_of(lambda: intermix.write_volume("x", "v.nii")) == (
        TypeError, "write_volume: volume must be an intermix.Volume, got str")
    assert message_of(lambda: intermix.Renderer(kept_budget="x")) == (
        TypeError, "Renderer: kept_budget must be an int, got str")
    assert message_of(lambda: intermix.to_uint8(IMAGE, "yes")) == (
        TypeError, "to_uint8: linear must be a bool (True or False), got str")
    assert message_of(lambda: intermix.Scene.from_json(5)) == (
        TypeError, "Scene.from_json: text must be a str, got int")
    assert message_of(lambda: s.add_volume(5, VOLUME)) == (
        TypeError, "Scene.add_volume: name must be a str, got int")
    assert message_of(lambda: intermix.read_mesh(MISSING, crease_angle_deg=math.nan)) == (
        ValueError, "read_mesh: crease_angle_deg nan is not a finite number")
    assert message_of(lambda: intermix.read_png(b"x.png")) == (
        TypeError, "read_png: path must be a path (a str or an os.PathLike), got bytes; decode "
                   "bytes paths with os.fsdecode")
    assert message_of(lambda: intermix.read_volume("a\0b.nii")) == (
        ValueError, "read_volume: path holds a NUL character")
    assert message_of(lambda: intermix.set_max_memory(2**63)) == (
        ValueError, "set_max_memory: bytes is 9223372036854775808, more than 9223372036854775807")


def test_exact_messages_for_calls_that_fit_no_signature():
    s = scene()
    assert message_of(lambda: s.render(widht=8)) == (
        TypeError, "Scene.render: got an unexpected keyword argument 'widht' (did you mean "
                   "'width'?); it takes (method=None, width=None, height=None, spp=None, "
                   "threads=None, view=None, colorbar=False, colorbar_scale=1.0)")
    assert message_of(lambda: intermix.Scene.set(1, 1)) == (
        TypeError, "Scene.set: self must be an intermix.Scene, got int")
    assert message_of(lambda: intermix.phantom("cube", 8, 9)) == (
        TypeError, "phantom: takes at most 2 positional arguments (name, size), got 3; it takes "
                   "(name, size=128)")
    assert message_of(lambda: intermix.read_volume(MISSING, "RAS")) == (
        TypeError, "read_volume: takes at most 1 positional argument (path), got 2; it takes "
                   "(path, *, space='LPS', series=None, units='', slice_spacing_mm=None, frame=0, recursive=False)")
    assert message_of(lambda: intermix.Mesh(VERTICES)) == (
        TypeError, "Mesh: missing the argument 'triangles'; it takes (vertices, triangles, "
                   "normals=None, colors=None, *, space='LPS', crease_angle_deg=60.0)")
    assert message_of(lambda: intermix.read_mesh(MISSING, path=MISSING))[1].startswith(
        "read_mesh: got 'path' twice, by position and by keyword")


def test_valid_values_of_every_accepted_kind(tmp_path):
    s = scene()
    # numpy integers are ints, numpy bools are bools, os.PathLike is a path.
    image = s.render(width=np.int64(8), height=np.int32(6), spp=np.uint8(1), threads=np.int16(1))
    assert image.shape == (6, 8, 4)
    intermix.write_png(image, tmp_path / "a.png", linear=np.bool_(False))
    assert intermix.read_png(pathlib.PurePath(tmp_path / "a.png")).shape == (6, 8, 4)
    assert intermix.error_heat_map(image, image, np.float32(4)).shape == (6, 8, 4)
    mesh = intermix.Mesh(VERTICES, TRIANGLES, crease_angle_deg=np.int64(30))
    assert mesh.normals.shape == (3, 3)
    r = intermix.Renderer(kept_budget=np.int64(1 << 20))
    r.kept_budget = 0
    assert r.kept_budget == 0
    assert intermix.phantom("cube", np.int64(8)).shape == (8, 8, 8)


def test_help_keeps_the_parameters_and_their_types():
    doc = intermix.Scene.render.__doc__
    assert doc.startswith("render(self: intermix._intermix.Scene, method: Optional[str] = None, "
                          "width: Optional[int] = None"), doc
    assert "Overloaded" not in doc
    assert intermix.read_volume.__doc__.startswith(
        "read_volume(path: Union[str, os.PathLike], *, space: str = 'LPS'")
    assert "size: int = 128" in intermix.phantom.__doc__


def test_a_message_quoting_bytes_that_are_not_utf8_keeps_its_text(tmp_path):
    # The parser quotes the file's first byte; a strict decode left the ValueError empty.
    (tmp_path / "scene.json").write_bytes(b"\x89PNG\r\n")
    with pytest.raises(ValueError) as e:
        intermix.Scene.from_file(tmp_path / "scene.json")
    assert str(e.value).startswith(f"{tmp_path}/scene.json: "), str(e.value)
    with pytest.raises(ValueError, match="^scene text: "):
        intermix.Scene.from_json("\x89PNG")


# ---- issue 48: the Python cases that showed pybind11 text or crashed ----


class RaisingPath:
    def __fspath__(self):
        raise RuntimeError("no path today")


def test_a_path_whose_fspath_raises_gets_one_line_without_pybind11s_traceback():
    kind, message = message_of(lambda: intermix.read_volume(RaisingPath()))
    assert (kind, message) == (
        TypeError, "read_volume: path: os.fspath failed on the test_binding_errors.RaisingPath: "
                   "RuntimeError: no path today")


def test_text_with_lone_surrogates_in_a_scene_is_refused_naming_where():
    # os.fsdecode gives such text for file names that are not UTF-8; pybind11 said "Unable to
    # cast Python instance to C++ type".
    assert message_of(lambda: scene().set("objects[0].name", "a\udcff")) == (
        ValueError, "scene dict: objects[0].name: 'a\\udcff' is not valid text (it holds lone "
                    "surrogates)")
    assert message_of(lambda: intermix.Scene.from_dict({"objects": [], "\udcff": 1})) == (
        ValueError, "scene dict: key '\\udcff' is not valid text (it holds lone surrogates)")


def test_an_int_past_a_doubles_range_in_a_scene_is_named():
    # Python's "int too large to convert to float" (an OverflowError) named nothing.
    assert message_of(lambda: scene().set("camera.fov_deg", -10**400)) == (
        ValueError, "scene dict: camera.fov_deg: an int of 401 digits is too large: numbers are "
                    "used as floats (at most 3.40282e+38)")


def test_classes_intermix_makes_say_so_when_called():
    for cls in (intermix.View, intermix.RendererStats):
        kind, message = message_of(cls)
        assert (kind, message) == (
            TypeError, f"intermix.{cls.__name__} is not made directly: intermix gives one "
                       f"(see help(intermix.{cls.__name__}))")


def test_pythons_own_messages_name_the_classes_without_the_extension_module():
    # Python names a type by its tp_name: "cannot pickle 'intermix._intermix.Scene' object".
    import pickle
    for call, message in [
            (lambda: pickle.dumps(scene()), "cannot pickle 'Scene' object"),
            (lambda: scene()[0], "'Scene' object is not subscriptable"),
            (lambda: pickle.dumps(VOLUME), "cannot pickle 'Volume' object")]:
        assert message_of(call) == (TypeError, message)

    class Unready(intermix.Scene):
        def __init__(self):
            pass

    assert message_of(Unready) == (
        TypeError, "Scene.__init__() must be called when overriding __init__")
    assert repr(intermix.View) == "<class 'intermix.View'>"


def test_an_instance_made_without_init_is_refused_not_a_crash():
    # Cls.__new__(Cls) holds no C++ object; reading it crashed (Volume's shape, a Renderer's
    # lock, a Scene passed to render).
    rc, out, err = run_python("""
import intermix
calls = [
    lambda: intermix.Volume.__new__(intermix.Volume).shape,
    lambda: intermix.Renderer.__new__(intermix.Renderer).render(
        intermix.Scene.from_dict({"objects": []})),
    lambda: intermix.Renderer().render(intermix.Scene.__new__(intermix.Scene)),
    lambda: intermix.write_volume(intermix.Volume.__new__(intermix.Volume), "never.nii"),
]
for call in calls:
    try:
        call()
    except TypeError as e:
        print(e)
""")
    assert rc == 0, err
    made = "made by {0}.__new__ and never initialized; make one with intermix.{0}(...) or the " \
           "function that gives one"
    assert out.splitlines() == [
        "Volume: a Volume " + made.format("Volume"),
        "Renderer.render: a Renderer " + made.format("Renderer"),
        "Renderer.render: a Scene " + made.format("Scene"),
        "write_volume: a Volume " + made.format("Volume")]


def test_a_null_is_named_once():
    assert message_of(lambda: scene().add_streamlines("t", None)) == (
        ValueError, "scene dict: objects[1].radius: expected a number, got null")


def run_python(code):
    """Runs `code` in a fresh interpreter (a crash there fails this test, not the session);
    returns (exit code, stdout, stderr)."""
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    return p.returncode, p.stdout, p.stderr


def test_a_numpy_longdouble_in_a_scene_is_a_number_or_refused_not_a_crash():
    # Its tolist() gives itself back: the conversion recursed until the stack ran out.
    rc, out, err = run_python("""
import numpy as np, intermix
s = intermix.Scene.from_dict({"objects": []})
s.set("camera.fov_deg", np.longdouble(30))
print(s.to_dict()["camera"]["fov_deg"])
s.set("camera.eye", np.array([1, 2, 3], np.longdouble))
print(s.to_dict()["camera"]["eye"])
for v in (np.longdouble("1e4000"), np.longdouble("inf")):
    try:
        s.set("camera.fov_deg", v)
    except ValueError as e:
        print(e)
""")
    assert rc == 0, err
    assert out.splitlines() == [
        "30.0", "[1.0, 2.0, 3.0]",
        "scene dict: camera.fov_deg: 1e+4000 is too large: numbers are used as floats (at most "
        "3.40282e+38)",
        "scene dict: camera.fov_deg: inf is not a finite number"]


def test_arrays_converted_with_warnings_as_errors_raise_not_crash():
    # numpy's overflow warning, made an error, left pybind11's array_t::ensure an empty array
    # that was then read (a segmentation fault), and a Volume said only "overflow encountered in
    # cast": the cast is quiet now, and intermix's own check names the value.
    rc, out, err = run_python("""
import warnings, numpy as np, intermix
warnings.simplefilter("error")
warnings.simplefilter("ignore", UserWarning)  # Volume's note that float64 is copied
big = np.full((4, 4, 4), 1e300)
calls = {
    "Volume": lambda: intermix.Volume(big, axes="kji"),
    "Mesh": lambda: intermix.Mesh(np.eye(3) * 1e300, np.array([[0, 1, 2]])),
    "Mesh colors": lambda: intermix.Mesh(np.eye(3), np.array([[0, 1, 2]]), colors=np.full((3, 3), 1e300)),
    "to_uint8": lambda: intermix.to_uint8(big),
    "write_png": lambda: intermix.write_png(big, "never.png"),
    "compare": lambda: intermix.compare(big, big),
}
for name, call in calls.items():
    try:
        call()
    except ValueError as e:
        print(e)
""")
    assert rc == 0, err
    assert out.splitlines() == [
        "Volume: array of shape (4, 4, 4): value 1e+300 at voxel (i, j, k) = (0, 0, 0) is beyond "
        "float32's range (+-3.4e38), which intermix holds floats in; scale the values first",
        "Mesh: vertex 0 at (inf, 0, 0) is not a finite position within 1e+06 mm of the origin",
        "Mesh: colors[0] = (inf, inf, inf) is not RGB in [0, 1]",
        "to_uint8: 64 of the image's 64 values are NaN or infinite; an image must be finite",
        "write_png: 64 of the image's 64 values are NaN or infinite; an image must be finite",
        "compare: a: 64 of the image's 64 values are NaN or infinite; an image must be finite"]
    # numpy's error state is left as it was.
    rc, out, err = run_python("""
import numpy as np, intermix
try:
    intermix.to_uint8(np.full((4, 4, 4), 1e300))
except ValueError:
    pass
print(np.geterr()["over"])
""")
    assert (rc, out) == (0, "warn\n"), err


def test_figure_arguments_are_named_with_their_values():
    s = scene()
    cases = [
        (lambda: intermix.orbit_cameras(None), TypeError,
         "orbit_cameras: camera must be a dict with eye, target and up, got NoneType"),
        (lambda: intermix.orbit_cameras(s), TypeError,
         "orbit_cameras: camera must be a dict with eye, target and up (a Scene's is "
         "scene.camera), got Scene"),
        (lambda: intermix.orbit_cameras(s.camera, frames=2**40), ValueError,
         "orbit_cameras: frames 1099511627776 is not in [1, 100000]"),
        (lambda: intermix.orbit(s, frames=2**40), ValueError,
         "orbit: frames 1099511627776 is not in [1, 100000]"),
        (lambda: intermix.orbit(s, 2, degrees=1e300), ValueError,
         "orbit: degrees 1e+300 is not in [-36000, 36000]"),
        (lambda: intermix.threshold_tf("a", "b"), TypeError,
         "threshold_tf: threshold must be a real number, got str"),
        (lambda: intermix.threshold_tf(1, 10**400), ValueError,
         "threshold_tf: vmax 1000000000000000... (401 characters) is not a finite number"),
        (lambda: intermix.ortho(VOLUME, cut_coords=[0, math.nan, 0]), ValueError,
         "ortho: cut_coords[1] nan is not a finite number"),
        (lambda: intermix.mosaic(VOLUME, cut_coords=2**40), ValueError,
         "mosaic: cut_coords 1099511627776 is not in [1, 64]"),
    ]
    for call, kind, message in cases:
        assert message_of(call) == (kind, message)


SHARED = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                      "..", "shared", "data")


def as_unprivileged_user():
    """The command prefix that runs as a user whom permissions stop ([] when this one is), or
    None when there is none (root without setpriv)."""
    if os.geteuid() != 0:
        return []
    if subprocess.run(["setpriv", "--version"], capture_output=True).returncode != 0:
        return None
    return ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"]


@pytest.mark.skipif(not os.path.isdir(os.path.join(SHARED, "dicom", "ct-philips")),
                    reason="no ../shared/data")
def test_a_dicom_series_it_may_not_read_raises_permission_error():
    # A slice that could not be opened was passed over as "not a DICOM image" (a missing-slice
    # ValueError), and then a ValueError saying "Permission denied".
    prefix = as_unprivileged_user()
    if prefix is None:
        pytest.skip("root without setpriv: no user that permissions stop")
    import shutil
    import tempfile
    with tempfile.TemporaryDirectory() as top:  # pytest's own folder is the owner's alone
        series = pathlib.Path(top) / "series"
        shutil.copytree(os.path.join(SHARED, "dicom", "ct-philips"), series)
        for f in series.iterdir():
            f.chmod(0o644)
        (series / "I120").chmod(0)
        for folder in (top, series):
            os.chmod(folder, 0o755)
        check_permission_error(prefix, series)


def check_permission_error(prefix, series):
    package = os.path.dirname(os.path.dirname(intermix.__file__))
    p = subprocess.run(prefix + [sys.executable, "-c", f"""
import intermix
for read in (intermix.read_volume, intermix.read_volume_info):
    try:
        read({str(series)!r})
    except OSError as e:
        print(type(e).__name__, e.errno, e)
"""], capture_output=True, text=True, timeout=120, env={**os.environ, "PYTHONPATH": package})
    assert p.returncode == 0, p.stderr
    line = f"PermissionError 13 {series}/I120: cannot open the file: Permission denied"
    assert p.stdout.splitlines() == [line, line]
