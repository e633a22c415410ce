// intermix.Volume (numpy voxels with an index-to-world affine), read_volume, write_volume and the
// built-in phantoms.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <limits>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/stl.h>
#include <glm/mat4x4.hpp>

#include "arguments.hpp"
#include "bindings.hpp"
#include "core/edit_distance.hpp"
#include "dicom_folder.hpp"
#include "intermix/dicom.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "io/voxels/frame_voxels.hpp"
#include "io/voxels/raw_voxels.hpp"

namespace imx::python {
namespace {

// make_phantom's sizes, as the scene loader's phantom "size" takes them.
constexpr int kMinPhantomSize = 8, kMaxPhantomSize = 1024;

// The engine's type for a numpy dtype it stores as it is ("" for any other).
const char* engine_dtype(const py::dtype& dtype) {
  if (!dtype.attr("isnative").cast<bool>()) return "";
  switch (dtype.kind()) {
    case 'u':
      return dtype.itemsize() == 1 ? "uint8" : dtype.itemsize() == 2 ? "uint16" : "";
    case 'i':
      return dtype.itemsize() == 2 ? "int16" : "";
    case 'f':
      return dtype.itemsize() == 4 ? "float32" : "";
    default:
      return "";
  }
}

// The engine type another dtype converts to, without loss where one of them holds every value:
// bool -> uint8, int8 -> int16, wider integers -> int16 or uint16 when their values fit, else
// float32; other floats -> float32.
const char* converted_dtype(const py::array& a) {
  const py::dtype dtype = a.dtype();
  switch (dtype.kind()) {
    case 'b':
      return "uint8";
    case 'f':
      return "float32";
    case 'u':
    case 'i': {
      if (dtype.itemsize() == 1) return dtype.kind() == 'u' ? "uint8" : "int16";
      if (a.size() == 0) return "int16";
      const double lo = a.attr("min")().cast<double>(), hi = a.attr("max")().cast<double>();
      if (lo >= -32768.0 && hi <= 32767.0) return "int16";
      if (lo >= 0.0 && hi <= 65535.0) return "uint16";
      return "float32";
    }
    default:
      throw py::type_error(
          fmt::format("Volume: voxels of dtype {} are not supported (integers, floats or bool)",
                      dtype.attr("name").cast<std::string>()));
  }
}

// Keeps a Python object alive from C++: the handle is released with the GIL held, whichever
// thread drops the last reference (none is taken once the interpreter is shutting down).
std::shared_ptr<const void> keep_alive(py::object object) {
  auto* held = new py::object(std::move(object));
  return std::shared_ptr<const void>(held, [](const void* p) {
    auto* object = static_cast<py::object*>(const_cast<void*>(p));
    if (!Py_IsInitialized() || _Py_IsFinalizing()) {
      object->release();  // too late to touch Python: leak the reference
      delete object;
      return;
    }
    py::gil_scoped_acquire gil;
    delete object;
  });
}

template <class T>
VoxelStorage view_of(const py::array& a) {
  return VoxelBuffer<T>::view(static_cast<const T*>(a.data()), static_cast<size_t>(a.size()),
                              keep_alive(a));
}

// The engine's voxels for a C-contiguous (k, j, i) array of an engine type: a view of the
// array's memory, which the volume keeps alive (no copy).
VoxelStorage voxel_storage(const py::array& a) {
  const std::string type = engine_dtype(a.dtype());
  if (type == "uint8") return view_of<uint8_t>(a);
  if (type == "int16") return view_of<int16_t>(a);
  if (type == "uint16") return view_of<uint16_t>(a);
  return view_of<float>(a);
}

glm::dmat4 affine_from(const py::handle& affine, const char* what) {
  py::array given =
      array_argument(affine, {what, "affine"}, "a 4x4 matrix of numbers", py::str("float64"));
  if (given.ndim() != 2 || given.shape(0) != 4 || given.shape(1) != 4)
    throw py::value_error(fmt::format("{}: the affine must be a 4x4 matrix, got shape {}", what,
                                      py::str(given.attr("shape")).cast<std::string>()));
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(given);
  auto r = a.unchecked<2>();
  glm::dmat4 m(1.0);
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) {
      if (!std::isfinite(r(row, col)))
        throw py::value_error(fmt::format("{}: affine[{}, {}] is {}, not a finite number", what,
                                          row, col, r(row, col)));
      m[col][row] = r(row, col);
    }
  const double last[4] = {0.0, 0.0, 0.0, 1.0};
  for (int col = 0; col < 4; ++col)
    if (r(3, col) != last[col])
      throw py::value_error(
          fmt::format("{}: the affine's last row is [{}, {}, {}, {}]; an affine needs [0, 0, 0, 1]",
                      what, r(3, 0), r(3, 1), r(3, 2), r(3, 3)));
  return m;
}

// RAS and LPS differ by the signs of x and y (a rotation by 180 degrees about z).
glm::dmat4 flip_xy(const glm::dmat4& m) {
  glm::dmat4 flip(1.0);
  flip[0][0] = flip[1][1] = -1.0;
  return flip * m;
}

py::array affine_array(const glm::dmat4& m) {
  py::array_t<double> a({4, 4});
  auto w = a.mutable_unchecked<2>();
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) w(row, col) = m[col][row];
  return a;
}

bool parse_space(const std::string& space, const char* what) {
  if (space == "LPS" || space == "lps") return true;
  if (space == "RAS" || space == "ras") return false;
  throw py::value_error(
      fmt::format("{}: space '{}' is not LPS or RAS (the affine's world axes)", what, space));
}

std::string shape_text(const py::array& a) {
  return py::str(a.attr("shape")).cast<std::string>();
}

// The order of `a`'s first three axes: "kji" or "ijk", as given, or for "auto" what the layout
// says. Only nibabel's layout says it: F order (and not C order) is (i, j, k), and so is any
// array given in RAS (nibabel's world). A C-contiguous array may be either (a copy of nibabel's
// data is C-ordered (i, j, k)), so is a slice with steps: auto refuses them instead of guessing.
std::string axis_order(const py::array& a, const std::string& axes, bool lps) {
  if (axes != "auto") return axes;
  if (!lps) return "ijk";
  const bool c_order = a.flags() & py::array::c_style;
  const bool f_order = a.flags() & py::array::f_style;
  if (f_order && !c_order) return "ijk";
  const std::string layout = c_order && f_order ? "an array contiguous in both C and F order"
                             : c_order          ? "a C-contiguous array"
                                                : "a non-contiguous array (a slice with steps, "
                                                  "a frame of a stack)";
  throw py::value_error(fmt::format(
      "Volume: axes='auto' cannot tell the axis order of {} of shape {}: name it, axes='kji' "
      "(array[k, j, i]: read_volume, SimpleITK) or axes='ijk' (array[i, j, k]: nibabel, whose "
      "affines are RAS: space='RAS' implies axes='ijk')",
      layout, shape_text(a)));
}

// One frame of an (i, j, k, ...) array as the file readers take frames: the axes beyond the
// third that hold one voxel are dropped, frames lie along the one that holds more (two such
// are refused), `frame` picks one (0-based); without it a 4-D array gives frame 0 with a
// warning. A view, no copy.
py::array frame_of(const py::array& ijk, const py::handle& frame_argument) {
  const std::optional<long long> frame =
      optional_int_in(frame_argument, {"Volume", "frame"}, 0, detail::kMaxFrames - 1);
  int along = -1;
  for (int d = 3; d < ijk.ndim(); ++d) {
    if (ijk.shape(d) <= 1) continue;
    if (along >= 0)
      throw py::value_error(fmt::format(
          "Volume: shape {} (as array[i, j, k, ...]) has frames along axes {} and {}; frames are "
          "read along one axis beyond the third, as from files",
          shape_text(ijk), along, d));
    along = d;
  }
  const long long frames = along < 0 ? 1 : ijk.shape(along);
  if (frame && *frame >= frames)
    throw py::value_error(
        frames == 1
            ? fmt::format("Volume: frame {} asked for, but the array holds one frame (0)", *frame)
            : fmt::format("Volume: frame {} asked for, but the array holds {} frames (0 "
                          "to {})",
                          *frame, frames, frames - 1));
  if (!frame && frames > 1) {
    const std::string message = fmt::format(
        "Volume: frame 0 of {} (shape {} as array[i, j, k, ...]); name another with frame=K",
        frames, shape_text(ijk));
    if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 1) < 0) throw py::error_already_set();
  }
  if (ijk.ndim() == 3) return ijk;
  const py::object all = py::module_::import("builtins").attr("slice")(py::none());
  py::tuple index(ijk.ndim());
  for (int d = 0; d < ijk.ndim(); ++d)
    index[d] = d < 3 ? all : py::object(py::int_(d == along ? frame.value_or(0) : 0));
  return ijk.attr("__getitem__")(index);
}

// A float64 value past float32's range would become inf in the float32 copy, which reads as "no
// data": refused instead, naming the first such voxel. Infinities given as such stay no data.
// `given` and `copy` are the (k, j, i) arrays.
void require_float32_range(const py::module_& np, const py::array& given, const py::array& copy,
                           const std::string& shape) {
  const py::object overflowed = np.attr("isinf")(copy);
  if (!overflowed.attr("any")().cast<bool>()) return;
  const py::object lost = np.attr("logical_and")(overflowed, np.attr("isfinite")(given));
  if (!lost.attr("any")().cast<bool>()) return;
  const py::tuple at = np.attr("unravel_index")(np.attr("argmax")(lost), given.attr("shape"));
  const double value = given[at].cast<double>();
  throw py::value_error(fmt::format(
      "Volume: array of shape {}: value {:g} at voxel (i, j, k) = ({}, {}, {}) is beyond "
      "float32's range (+-3.4e38), which intermix holds floats in; scale the values first",
      shape, value, at[2].cast<long>(), at[1].cast<long>(), at[0].cast<long>()));
}

std::shared_ptr<PyVolume> make_volume(const ArrayParameter& given,
                                      const OptionalArrayParameter& affine_argument,
                                      const OptionalTextParameter& space_argument,
                                      const TextParameter& axes_argument,
                                      const OptionalIntParameter& frame_argument) {
  py::module_ np = py::module_::import("numpy");
  const std::optional<std::string> space_given = optional_text(space_argument, {"Volume", "space"});
  std::string axes = text(axes_argument, {"Volume", "axes"});
  if (axes != "auto" && axes != "kji" && axes != "ijk")
    throw py::value_error(fmt::format(
        "Volume: axes '{}' is not auto, kji (array[k, j, i], C order) or ijk (array[i, j, k], "
        "nibabel's order)",
        axes));
  bool lps = parse_space(space_given.value_or("LPS"), "Volume");
  py::object affine = affine_argument;
  py::object source = given;
  // A nibabel image (or an object like one), or its dataobj: its voxels as the file readers
  // read the file, in nibabel's (i, j, k) order, with the image's RAS affine.
  py::module_ images = py::module_::import("intermix._images");
  const bool is_array = py::isinstance<py::array>(given);
  const bool image = !is_array && images.attr("is_image")(given).cast<bool>();
  if (image || (!is_array && images.attr("is_array_proxy")(given).cast<bool>())) {
    const py::tuple read = images.attr("image_voxels")(given);
    source = read[0];
    if (image) {
      if (!affine.is_none())
        throw py::value_error(
            "Volume: the image carries its own affine (img.affine); give no affine with it");
      if (space_given && lps)
        throw py::value_error(fmt::format(
            "Volume: space '{}' given for a nibabel image, whose affine is RAS", *space_given));
      affine = read[1];
      lps = false;
    }
    if (axes == "kji")
      throw py::value_error(
          "Volume: axes 'kji' given for a nibabel image or dataobj, whose arrays are (i, j, k)");
    axes = "ijk";
  }
  // An ndarray subclass (a memmap) stays one; anything else becomes an array.
  py::array a = py::isinstance<py::array>(source)
                    ? py::reinterpret_borrow<py::array>(source)
                    : array_argument(source, {"Volume", "array"}, "an array of voxels");
  if (a.ndim() < 3)
    throw py::value_error(fmt::format(
        "Volume: expected a 3-D array, got {} dimensions with shape {}", a.ndim(), shape_text(a)));
  if (a.ndim() > 7)
    throw py::value_error(
        fmt::format("Volume: shape {} has {} dimensions; a volume has 3, and frames one more",
                    shape_text(a), a.ndim()));
  const std::string order = axis_order(a, axes, lps);
  // Frames follow the three spatial axes in (i, j, k) order: a (k, j, i) array's precede them.
  const py::array ijk_all = order == "ijk" ? a : py::array(a.attr("transpose")());
  const py::array ijk = frame_of(ijk_all, frame_argument);
  // Sizes before anything reads or copies the array: a view with zero strides (broadcast_to,
  // as_strided) claims far more voxels than its memory holds.
  const std::string shape = shape_text(a);  // as the caller knows it
  double voxels = 1.0;
  for (int d = 0; d < 3; ++d) {
    if (ijk.shape(d) < 1 || ijk.shape(d) > std::numeric_limits<int>::max())
      throw py::value_error(fmt::format("Volume: shape {}: each axis needs 1 to {} voxels", shape,
                                        std::numeric_limits<int>::max()));
    voxels *= static_cast<double>(ijk.shape(d));
  }
  if (voxels > static_cast<double>(detail::kMaxVoxels))
    throw py::value_error(fmt::format("Volume: shape {} holds {:.0f} voxels, more than {}", shape,
                                      voxels, detail::kMaxVoxels));
  py::array kji = ijk.attr("transpose")();
  const std::string type = engine_dtype(kji.dtype());
  const bool in_place = !type.empty() && (kji.flags() & py::array::c_style);
  if (!in_place) {
    const char* target = type.empty() ? converted_dtype(kji) : type.c_str();
    const uint64_t copy_bytes = static_cast<uint64_t>(voxels) * py::dtype(target).itemsize();
    check_memory(copy_bytes, fmt::format("Volume: a {} copy of the {} array of shape {}", target,
                                         py::str(kji.dtype()).cast<std::string>(), shape));
    // float64 is nibabel's get_fdata() default: the copy is avoidable, so say how.
    if (kji.dtype().kind() == 'f' && kji.dtype().itemsize() >= 8) {
      const std::string message = fmt::format(
          "Volume: float64 voxels are copied to float32 ({:.1f} MiB); nibabel's "
          "img.get_fdata(dtype=np.float32), or img.dataobj (the file's own type, viewed without "
          "a copy), or intermix.Volume(img) avoids the copy",
          static_cast<double>(copy_bytes) / (1 << 20));
      if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 1) < 0) throw py::error_already_set();
    }
    const py::array given = kji;
    {
      const QuietOverflow quiet;  // require_float32_range names such a value
      kji = np.attr("ascontiguousarray")(kji, py::arg("dtype") = target);
    }
    if (given.dtype().kind() == 'f' && given.dtype().itemsize() > 4)
      require_float32_range(np, given, kji, shape);
  }
  auto v = std::make_shared<PyVolume>();
  v->id = next_source_id("volume");
  v->given = source;
  v->array = kji;
  v->lps = lps;
  VolumeData data;
  data.dims = {static_cast<int>(kji.shape(2)), static_cast<int>(kji.shape(1)),
               static_cast<int>(kji.shape(0))};
  const glm::dmat4 m = affine.is_none() ? glm::dmat4(1.0) : affine_from(affine, "Volume");
  data.index_to_world = v->lps ? m : flip_xy(m);
  data.voxels = voxel_storage(kji);
  v->shares_memory = in_place;
  data.validate("Volume");
  v->data = std::make_shared<const VolumeData>(std::move(data));
  return v;
}

// The voxels of `data` as a (nk, nj, ni) C-order array that keeps `data` alive (no copy).
py::array voxels_array(const std::shared_ptr<const VolumeData>& data, bool writeable) {
  const void* voxels =
      std::visit([](const auto& v) -> const void* { return v.data(); }, data->voxels);
  return view_array(voxels, py::dtype(voxel_type_name(data->type())),
                    {data->dims.z, data->dims.y, data->dims.x}, data, writeable);
}

// A DICOM series as read_volume takes it: its number (an int), id or UID (a str), or None.
std::optional<std::string> series_of(const py::handle& series, const Argument& argument) {
  if (series.is_none() || PyUnicode_Check(series.ptr())) return optional_text(series, argument);
  if (is_int_like(series))
    return std::to_string(int_in(series, argument, 0, std::numeric_limits<int>::max()));
  throw_wrong_type(argument, "a str or an int (a series number, id or UID)", series);
}

py::tuple read_volume_file(const PathParameter& path, const TextParameter& space_argument,
                           const SeriesParameter& series_argument,
                           const TextParameter& units_argument,
                           const OptionalRealParameter& slice_spacing_argument,
                           const IntParameter& frame_argument,
                           const FlagParameter& recursive_argument) {
  const std::filesystem::path file = python::path(path, {"read_volume", "path"});
  const bool recursive = flag(recursive_argument, {"read_volume", "recursive"});
  const bool lps = parse_space(text(space_argument, {"read_volume", "space"}), "read_volume");
  const std::optional<std::string> series = series_of(series_argument, {"read_volume", "series"});
  const std::string units = text(units_argument, {"read_volume", "units"});
  const std::optional<double> slice_spacing_mm =
      optional_finite_real(slice_spacing_argument, {"read_volume", "slice_spacing_mm"});
  // Frames are counted from 0; no file may hold more than kMaxFrames.
  const int frame =
      static_cast<int>(int_in(frame_argument, {"read_volume", "frame"}, 0, detail::kMaxFrames - 1));
  DicomReadOptions options;
  if (series) options.series = *series;
  options.units = units;
  options.slice_spacing_mm = slice_spacing_mm;
  options.frame = frame;
  const bool dicom_options = series || !units.empty() || slice_spacing_mm;
  if (!units.empty() && units != "suv")
    throw py::value_error(fmt::format("read_volume: units '{}' is not suv", units));
  std::shared_ptr<VolumeData> data;
  {
    py::gil_scoped_release release;  // large files take seconds
    if (is_dicom_source(file)) {
      read_dicom_source(file, recursive, "read_volume", [&](const std::filesystem::path& source) {
        data = std::make_shared<VolumeData>(read_dicom(source, options).volume);
      });
    } else {
      if (dicom_options)
        throw Error(fmt::format(
            "{}: only DICOM sources (a folder, DICOMDIR or .dcm file) take series, units and "
            "slice_spacing_mm",
            file.string()));
      data = std::make_shared<VolumeData>(read_volume(file, frame));
    }
    data->validate(file.string());
  }
  const glm::dmat4 affine = lps ? data->index_to_world : flip_xy(data->index_to_world);
  return py::make_tuple(voxels_array(data, true), affine_array(affine));
}

// What a file holds without its voxels: dims, type, frames and their labels.
py::dict read_volume_info(const PathParameter& path, const SeriesParameter& series_argument,
                          const FlagParameter& recursive_argument) {
  const std::filesystem::path file = python::path(path, {"read_volume_info", "path"});
  const bool recursive = flag(recursive_argument, {"read_volume_info", "recursive"});
  const std::optional<std::string> series =
      series_of(series_argument, {"read_volume_info", "series"});
  VolumeHeader h;
  {
    py::gil_scoped_release release;
    if (is_dicom_source(file)) {
      DicomReadOptions options;
      if (series) options.series = *series;
      read_dicom_source(
          file, recursive, "read_volume_info",
          [&](const std::filesystem::path& source) { h = read_dicom_header(source, options); });
    } else {
      h = read_volume_header(file);
    }
  }
  py::list labels;
  for (const FrameLabel& l : h.frame_labels) {
    py::dict d;
    d["label"] = l.text;
    if (l.time_s) d["time_s"] = *l.time_s;
    if (l.b_value) d["b_value"] = *l.b_value;
    if (l.b_vector) d["b_vector"] = py::make_tuple(l.b_vector->x, l.b_vector->y, l.b_vector->z);
    if (l.echo_time_ms) d["echo_time_ms"] = *l.echo_time_ms;
    if (l.trigger_time_ms) d["trigger_time_ms"] = *l.trigger_time_ms;
    if (!l.image_type.empty()) d["image_type"] = l.image_type;
    labels.append(d);
  }
  py::dict out;
  out["shape"] = py::make_tuple(h.dims.z, h.dims.y, h.dims.x);
  out["frames"] = h.frames;
  out["frame_labels"] = labels;
  return out;
}

}  // namespace

std::string next_source_id(const char* kind) {
  static std::atomic<long long> counter{0};
  return fmt::format("{}-{}", kind, ++counter);
}

py::array view_array(const void* data, const py::dtype& dtype, std::vector<py::ssize_t> shape,
                     std::shared_ptr<const void> owner, bool writeable) {
  auto* holder = new std::shared_ptr<const void>(std::move(owner));
  py::capsule base(holder, [](void* p) { delete static_cast<std::shared_ptr<const void>*>(p); });
  py::array a(dtype, std::move(shape), {}, const_cast<void*>(data), base);
  if (!writeable) a.attr("setflags")(py::arg("write") = false);
  return a;
}

void bind_volume(py::module_& m) {
  // Whether voxels of an engine type are read in place (VoxelBuffer views) or copied.
  m.attr("_zero_copy") = py::bool_(true);
  py::class_<PyVolume, std::shared_ptr<PyVolume>>(
      m, "Volume",
      R"doc(A volume from numpy or nibabel: voxels with a 4x4 index-to-world affine (millimetres), usable
as a volume object's "source" in a scene (Scene.from_dict, Scene.add_volume, Scene.set).

Volume(array, affine=None, *, space=None, axes="auto", frame=None)
Volume(img, *, frame=None)      a nibabel image (or an object with .dataobj or .get_fdata, and
                                .affine): read as intermix reads its file (dataobj's own type and
                                the header's scaling, the RAS affine, nibabel's (i, j, k) axes)

array: the voxels. The affine maps voxel indices (i, j, k, 1) to world (x, y, z, 1). The array's
  axis order must be known, never guessed:
  - axes="kji": array[k, j, i], shape (nk, nj, ni) (read_volume, SimpleITK's GetArrayFromImage);
  - axes="ijk": array[i, j, k], shape (ni, nj, nk) (nibabel's get_fdata() and dataobj);
  - axes="auto" (the default) is "ijk" for space="RAS" (nibabel's world) and for an F-ordered
    array (nibabel's layout), and refuses any other array (C-contiguous or non-contiguous),
    naming axes: a C-ordered copy of nibabel data would otherwise be read transposed.
  Axes beyond the third are frames, as in files: those of one voxel are dropped, `frame` picks
  one along the other (without it a 4-D array gives frame 0 and a warning). Frames follow the
  spatial axes in (i, j, k) order and precede them in (k, j, i) order.
  uint8, int16, uint16 and float32 arrays in native byte order whose memory is C-ordered
  (k, j, i) are used without a copy (the engine reads the array's memory, and the Volume keeps
  the array alive; do not modify it afterwards). Anything else is converted and copied once:
  bool -> uint8, int8 -> int16, wider integers -> int16 or uint16 when every value fits, else
  float32, other floats -> float32 (float64 with a warning: it doubles the memory, and
  get_fdata(dtype=np.float32) or dataobj avoid it).
affine: 4x4 array-like, last row [0, 0, 0, 1]; None is the identity (1 mm voxels at the origin).
space: the affine's world axes: "LPS" (DICOM, ITK, intermix; the default) or "RAS" (NIfTI,
  nibabel, Slicer). RAS is turned into LPS by negating x and y.

Raises ValueError (with the library's message) for bad shapes or affines. NaN and inf voxels
are no data: they render as nothing.
)doc")
      .def(py::init(&make_volume), py::arg("array"), py::arg("affine") = py::none(), py::kw_only(),
           py::arg("space") = py::none(), py::arg("axes") = "auto", py::arg("frame") = py::none())
      .def_property_readonly(
          "array", [](const PyVolume& v) { return v.given; },
          "The array as it was given (kept alive as long as the volume).")
      .def_property_readonly(
          "voxels", [](const PyVolume& v) { return v.array; },
          "The voxels as the engine reads them: a C-order (nk, nj, ni) array of uint8, int16, "
          "uint16 or float32 (the given array, a view of it, or its converted copy).")
      .def_property_readonly(
          "affine",
          [](const PyVolume& v) {
            return affine_array(v.lps ? v.data->index_to_world : flip_xy(v.data->index_to_world));
          },
          "The 4x4 index-to-world affine in the space it was given.")
      .def_property_readonly(
          "lps_affine", [](const PyVolume& v) { return affine_array(v.data->index_to_world); },
          "The 4x4 index-to-world affine in LPS, as the engine uses it.")
      .def_property_readonly(
          "shape",
          [](const PyVolume& v) {
            return py::make_tuple(v.data->dims.x, v.data->dims.y, v.data->dims.z);
          },
          "Voxels along i, j, k: (ni, nj, nk).")
      .def_property_readonly(
          "dtype", [](const PyVolume& v) { return py::dtype(voxel_type_name(v.data->type())); },
          "The engine's voxel type: uint8, int16, uint16 or float32.")
      .def_property_readonly(
          "spacing",
          [](const PyVolume& v) {
            const glm::dvec3 s = v.data->spacing();
            return py::make_tuple(s.x, s.y, s.z);
          },
          "Millimetres per index step along i, j, k (lengths of the affine's columns).")
      .def_property_readonly(
          "range",
          [](const PyVolume& v) {
            auto [lo, hi] = v.data->range();
            return py::make_tuple(lo, hi);
          },
          "The smallest and largest finite voxel value (NaN and inf are no data).")
      .def_property_readonly(
          "shares_memory", [](const PyVolume& v) { return v.shares_memory; },
          "True when the engine reads the given array's own memory (no copy was made).")
      .def_property_readonly(
          "_data_address",
          [](const PyVolume& v) {
            return reinterpret_cast<uintptr_t>(
                std::visit([](const auto& s) -> const void* { return s.data(); }, v.data->voxels));
          },
          "The address of the voxels the engine reads (for tests of the zero-copy path).")
      .def("__repr__", [](const PyVolume& v) {
        const glm::dvec3 s = v.data->spacing();
        return fmt::format("<intermix.Volume {}x{}x{} {} spacing {:g}x{:g}x{:g} mm{}>",
                           v.data->dims.x, v.data->dims.y, v.data->dims.z,
                           voxel_type_name(v.data->type()), s.x, s.y, s.z,
                           v.shares_memory ? ", shares the array's memory" : "");
      });

  m.def(
      "read_volume", &read_volume_file, py::arg("path"), py::kw_only(), py::arg("space") = "LPS",
      py::arg("series") = py::none(), py::arg("units") = "",
      py::arg("slice_spacing_mm") = py::none(), py::arg("frame") = 0, py::arg("recursive") = false,
      R"doc(Reads a volume file: NRRD (.nrrd, .nhdr), NIfTI (.nii, .nii.gz, .hdr/.img), MGH (.mgh, .mgz),
MetaImage (.mha, .mhd), or a DICOM folder, DICOMDIR or file: its largest series, or `series` (a
number, id or UID), in `units="suv"` for PET, resampled to `slice_spacing_mm` when its slices are
uneven (as `intermix convert` reads it). Of a multi-frame (4-D) file or series (fMRI, DWI, ASL,
echoes), `frame` picks one (0-based); read_volume_info says how many there are.

Returns (array, affine): the voxels as a C-order (nk, nj, ni) array of uint8, int16, uint16 or
float32 (indexed array[k, j, i]) and the 4x4 index-to-world affine in `space` ("LPS", the default,
or "RAS"). Volume(array, affine, space=space, axes="kji") gives the same volume back without a
copy. A folder is searched for DICOM files in itself only, unless `recursive`.
Raises OSError when the file cannot be read, ValueError when its content is wrong.
)doc");
  m.def(
      "read_volume_info", &read_volume_info, py::arg("path"), py::kw_only(),
      py::arg("series") = py::none(), py::arg("recursive") = false,
      R"doc(What a volume file or DICOM series holds without reading its voxels: a dict with "shape"
(nk, nj, ni), "frames" (1 for a 3-D volume) and "frame_labels" (one dict per frame, with "label"
and, where the file says, "time_s", "b_value", "b_vector" (along i, j, k), "echo_time_ms",
"trigger_time_ms", "image_type"; empty when the file labels nothing).
)doc");

  m.def(
      "write_volume",
      [](const VolumeParameter& volume, const PathParameter& path,
         const FlagParameter& compress_argument) {
        const PyVolume& v =
            instance_of<PyVolume>(volume, {"write_volume", "volume"}, "an intermix.Volume");
        const std::filesystem::path file = python::path(path, {"write_volume", "path"});
        const bool compress = flag(compress_argument, {"write_volume", "compress"});
        py::gil_scoped_release release;
        write_volume(*v.data, file, compress);
      },
      py::arg("volume"), py::arg("path"), py::kw_only(), py::arg("compress") = true,
      R"doc(Writes a Volume as NIfTI-1 (.nii.gz, .nii), NRRD (.nrrd) or MetaImage (.mha) by the extension,
atomically. `compress` applies to NRRD and MetaImage (NIfTI follows the .gz).
)doc");

  m.def("phantom_names", &phantom_names, "Names of the built-in volume phantoms.");
  m.def(
      "phantom",
      [](const TextParameter& name_argument, const IntParameter& size_argument) {
        const std::string name = text(name_argument, {"phantom", "name"});
        const int size = static_cast<int>(
            int_in(size_argument, {"phantom", "size"}, kMinPhantomSize, kMaxPhantomSize));
        const std::vector<std::string> names = phantom_names();
        if (std::find(names.begin(), names.end(), name) == names.end())
          throw py::value_error(
              fmt::format("phantom: name '{}' is not a built-in phantom{}; they are: {}", name,
                          did_you_mean(name, names), fmt::join(names, ", ")));
        std::shared_ptr<VolumeData> data;
        {
          py::gil_scoped_release release;
          data = std::make_shared<VolumeData>(make_phantom(name, size));
        }
        py::array voxels = voxels_array(data, false);
        auto v = std::make_shared<PyVolume>();
        v->id = next_source_id("volume");
        v->given = voxels;
        v->array = voxels;
        v->shares_memory = true;
        v->data = data;
        return v;
      },
      py::arg("name"), py::arg("size") = 128,
      R"doc(A built-in phantom as a Volume (intermix.phantom_names(): ct-head, cube, ellipsoid, pet, shells,
sphere); `size` is the voxel count along its largest axis. Its array is read-only.
)doc");
}

}  // namespace imx::python
