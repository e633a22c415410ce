// intermix.Streamlines: a tractogram from a file (the format registry's readers) or from arrays
// (nibabel's Tractogram and ArraySequence, DIPY's StatefulTractogram and lists of arrays, numpy
// points with offsets), read through the buffer protocol straight into imx::Streamlines.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>

#include <fmt/format.h>
#include <pybind11/stl.h>
#include <glm/mat4x4.hpp>

#include "arguments.hpp"
#include "bindings.hpp"
#include "core/limits.hpp"
#include "io/streamlines/streamline_formats.hpp"

namespace imx::python {
namespace {

constexpr const char* kClass = "Streamlines";
// Offsets are 32-bit: the points of one tractogram stay below 2**32.
constexpr int64_t kMaxPoints = std::numeric_limits<uint32_t>::max();

// RAS mm (nibabel's and DIPY's world) into intermix's LPS: x and y negated.
const glm::dmat4 kLpsFromRas(glm::dvec4(-1, 0, 0, 0), glm::dvec4(0, -1, 0, 0),
                             glm::dvec4(0, 0, 1, 0), glm::dvec4(0, 0, 0, 1));

std::string shape_text(const py::buffer_info& info) {
  std::string s = "(";
  for (size_t d = 0; d < info.shape.size(); ++d)
    s += fmt::format("{}{}", d ? ", " : "", info.shape[d]);
  return s + (info.shape.size() == 1 ? ",)" : ")");
}

// An (n, k) or (n,) array of numbers seen through the buffer protocol: float32 and float64 are
// read where they lie; other types (ints, float16, the other byte order, nested lists) are
// converted by numpy first, to float64.
struct Rows {
  py::object holder;  // the object whose buffer this is (a numpy conversion, when one was made)
  py::buffer_info info;
  char type = 'd';  // 'f' float32, 'd' float64
  py::ssize_t rows = 0, columns = 1, row_stride = 0, column_stride = 0;
};

bool native_float(const std::string& format, char& type) {
  std::string f = format;
  if (!f.empty() && (f[0] == '@' || f[0] == '=' || f[0] == '<')) f.erase(0, 1);  // little-endian
  if (f == "f" || f == "d") {
    type = f[0];
    return true;
  }
  return false;
}

// `value` as Rows of `columns` columns (-1: one column, a 1-D array, or any number of them);
// `what` names it in errors after "Streamlines: " ("points", "streamline 3").
Rows rows_of(const py::handle& value, const std::string& what, int columns) {
  Rows r;
  bool readable = false;
  if (PyObject_CheckBuffer(value.ptr())) {
    r.holder = py::reinterpret_borrow<py::object>(value);
    r.info = py::reinterpret_borrow<py::buffer>(value).request();
    readable = native_float(r.info.format, r.type);
  }
  if (!readable) {
    r.holder = array_argument(value, {kClass, what}, "an array of numbers", py::dtype("float64"));
    r.info = py::reinterpret_borrow<py::buffer>(r.holder).request();
    r.type = 'd';
  }
  const py::buffer_info& info = r.info;
  const bool rows_of_k = info.ndim == 2 && (columns < 0 || info.shape[1] == columns);
  const bool column = info.ndim == 1 && columns <= 1;
  if (!rows_of_k && !column)
    throw py::value_error(fmt::format("{}: {} must have shape ({}), got {}", kClass, what,
                                      columns == 3   ? "n, 3"
                                      : columns == 1 ? "n,"
                                                     : "n, k",
                                      shape_text(info)));
  r.rows = info.shape[0];
  r.row_stride = info.strides[0];
  if (info.ndim == 2) {
    r.columns = info.shape[1];
    r.column_stride = info.strides[1];
  }
  return r;
}

template <class T>
T at(const Rows& r, py::ssize_t row, py::ssize_t column) {
  T v;
  std::memcpy(&v,
              static_cast<const char*>(r.info.ptr) + row * r.row_stride + column * r.column_stride,
              sizeof(T));
  return v;
}

// Rows [first, first + n) of (x, y, z) rows, mapped by `to_lps`, into `out`.
template <class T>
void copy_points_as(const Rows& r, py::ssize_t first, py::ssize_t n, const glm::dmat4& to_lps,
                    glm::vec3* out) {
  for (py::ssize_t i = 0; i < n; ++i) {
    const glm::dvec4 p(at<T>(r, first + i, 0), at<T>(r, first + i, 1), at<T>(r, first + i, 2), 1.0);
    out[i] = glm::vec3(to_lps * p);
  }
}

void copy_points(const Rows& r, py::ssize_t first, py::ssize_t n, const glm::dmat4& to_lps,
                 glm::vec3* out) {
  if (r.type == 'f')
    copy_points_as<float>(r, first, n, to_lps, out);
  else
    copy_points_as<double>(r, first, n, to_lps, out);
}

void copy_column(const Rows& r, py::ssize_t first, py::ssize_t n, py::ssize_t column, float* out) {
  for (py::ssize_t i = 0; i < n; ++i)
    out[i] = r.type == 'f' ? at<float>(r, first + i, column)
                           : static_cast<float>(at<double>(r, first + i, column));
}

// A 1-D integer array (offsets, lengths) as int64 values.
std::vector<int64_t> integers(const py::handle& value, const std::string& what) {
  py::array a = array_argument(value, {kClass, what}, "a 1-D array of integers");
  if (a.ndim() != 1)
    throw py::value_error(fmt::format("{}: {} must be 1-D, got shape {}", kClass, what,
                                      py::str(a.attr("shape")).cast<std::string>()));
  if (a.size() > 0 && a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
    throw py::type_error(fmt::format("{}: {} must be integers, got dtype {}", kClass, what,
                                     py::str(a.dtype()).cast<std::string>()));
  auto i64 = py::array_t<int64_t, py::array::forcecast>::ensure(a);
  if (!i64)
    throw py::value_error(fmt::format("{}: {} holds integers beyond 64 bits", kClass, what));
  std::vector<int64_t> out(static_cast<size_t>(i64.size()));
  for (size_t i = 0; i < out.size(); ++i) out[i] = i64.at(static_cast<py::ssize_t>(i));
  return out;
}

// The total of `lengths`, refused beyond what 32-bit offsets hold.
int64_t total_points(const std::vector<int64_t>& lengths) {
  int64_t total = 0;
  for (int64_t n : lengths) {
    total += n;
    if (total > kMaxPoints)
      throw py::value_error(
          fmt::format("{}: more than {} points (offsets are 32-bit)", kClass, kMaxPoints));
  }
  return total;
}

void set_offsets(Streamlines& s, const std::vector<int64_t>& lengths) {
  s.offsets.resize(lengths.size() + 1);
  s.offsets[0] = 0;
  for (size_t i = 0; i < lengths.size(); ++i)
    s.offsets[i + 1] = s.offsets[i] + static_cast<uint32_t>(lengths[i]);
}

// nibabel's ArraySequence: streamline i is _data[_offsets[i] : _offsets[i] + _lengths[i]]
// (a slice of one may leave gaps or reorder them).
struct Sequence {
  Rows data;
  std::vector<int64_t> starts, lengths;
  bool packed = true;  // streamline i follows i - 1 with no gap: one block copy
};

bool is_array_sequence(const py::handle& value) {
  return py::hasattr(value, "_data") && py::hasattr(value, "_offsets") &&
         py::hasattr(value, "_lengths");
}

Sequence sequence_of(const py::handle& seq, const std::string& what, int columns) {
  Sequence s;
  s.starts = integers(seq.attr("_offsets"), what + "._offsets");
  s.lengths = integers(seq.attr("_lengths"), what + "._lengths");
  if (s.starts.size() != s.lengths.size())
    throw py::value_error(fmt::format("{}: {}._offsets holds {} values but _lengths {}", kClass,
                                      what, s.starts.size(), s.lengths.size()));
  py::object data = seq.attr("_data");
  if (s.starts.empty()) return s;  // nibabel's empty sequence has a (0,) _data
  s.data = rows_of(data, what + "._data", columns);
  int64_t next = 0;
  for (size_t i = 0; i < s.starts.size(); ++i) {
    const int64_t start = s.starts[i], n = s.lengths[i];
    if (start < 0 || n < 0 || start > s.data.rows || n > s.data.rows - start)
      throw py::value_error(
          fmt::format("{}: {}: streamline {} lies at _data[{}:{}], outside the {} rows of _data",
                      kClass, what, i, start, start + n, s.data.rows));
    s.packed = s.packed && start == next;
    next = start + n;
  }
  return s;
}

void copy_sequence_points(const Sequence& seq, const glm::dmat4& to_lps, Streamlines& out) {
  set_offsets(out, seq.lengths);
  out.points.resize(static_cast<size_t>(total_points(seq.lengths)));
  py::gil_scoped_release release;  // the buffers stay held by `seq`
  if (seq.packed) {
    copy_points(seq.data, 0, static_cast<py::ssize_t>(out.points.size()), to_lps,
                out.points.data());
    return;
  }
  for (size_t i = 0; i < seq.starts.size(); ++i)
    copy_points(seq.data, seq.starts[i], seq.lengths[i], to_lps,
                out.points.data() + out.offsets[i]);
}

// Every column of `rows` as a named value array: "fa", or "rgb[0]".."rgb[2]" as the TRK reader
// names a value of several columns.
void add_values(std::vector<StreamlineValues>& list, const std::string& name, size_t size,
                py::ssize_t columns, const std::function<void(py::ssize_t, float*)>& fill) {
  for (py::ssize_t c = 0; c < columns; ++c) {
    StreamlineValues v{columns == 1 ? name : fmt::format("{}[{}]", name, c),
                       std::vector<float>(size)};
    for (const StreamlineValues& other : list)
      if (other.name == v.name)
        throw py::value_error(fmt::format("{}: two values are named '{}'", kClass, v.name));
    fill(c, v.values.data());
    list.push_back(std::move(v));
  }
}

// Per-point values whose streamlines are `seq`'s (a Tractogram's data_per_point entry).
void add_sequence_point_values(Streamlines& out, const std::string& name, const py::handle& value) {
  const std::string what = fmt::format("data_per_point['{}']", name);
  if (!is_array_sequence(value))
    throw py::type_error(fmt::format("{}: {} is not an ArraySequence", kClass, what));
  const Sequence seq = sequence_of(value, what, -1);
  if (seq.lengths.size() != out.count())
    throw py::value_error(fmt::format("{}: {} has {} streamlines, the tractogram {}", kClass, what,
                                      seq.lengths.size(), out.count()));
  for (size_t i = 0; i < seq.lengths.size(); ++i)
    if (seq.lengths[i] != static_cast<int64_t>(out.length(i)))
      throw py::value_error(
          fmt::format("{}: {} has {} values for streamline {}, which has {} points", kClass, what,
                      seq.lengths[i], i, out.length(i)));
  add_values(out.point_values, name, out.points.size(), seq.data.columns,
             [&](py::ssize_t c, float* dst) {
               for (size_t i = 0; i < seq.starts.size(); ++i)
                 copy_column(seq.data, seq.starts[i], seq.lengths[i], c, dst + out.offsets[i]);
             });
}

// One array per point or per streamline: `rows` rows of one value or several.
void add_array_values(std::vector<StreamlineValues>& list, const std::string& name,
                      const py::handle& value, size_t expected, const char* per,
                      const std::string& what) {
  const Rows r = rows_of(value, what, -1);
  if (static_cast<size_t>(r.rows) != expected)
    throw py::value_error(fmt::format("{}: {} has {} rows, but there are {} {}", kClass, what,
                                      r.rows, expected, per));
  add_values(list, name, expected, r.columns,
             [&](py::ssize_t c, float* dst) { copy_column(r, 0, r.rows, c, dst); });
}

// The (name, array) pairs of a mapping, in its order.
std::vector<std::pair<std::string, py::object>> named_arrays(const py::handle& mapping,
                                                             const Argument& argument) {
  if (!py::hasattr(mapping, "items")) throw_wrong_type(argument, "a dict of name: array", mapping);
  std::vector<std::pair<std::string, py::object>> out;
  for (const py::handle item : mapping.attr("items")()) {
    const py::tuple kv = py::reinterpret_borrow<py::tuple>(item);
    out.emplace_back(text(kv[0], argument), py::reinterpret_borrow<py::object>(kv[1]));
  }
  return out;
}

// A DIPY-style list (any iterable) of (n, 3) arrays: counted first, then copied each.
void copy_list_points(const py::handle& items, const glm::dmat4& to_lps, Streamlines& out) {
  const py::list list(py::reinterpret_borrow<py::object>(items));
  std::vector<int64_t> lengths(list.size());
  for (size_t i = 0; i < lengths.size(); ++i)
    lengths[i] = rows_of(list[i], fmt::format("streamline {}", i), 3).rows;
  set_offsets(out, lengths);
  out.points.resize(static_cast<size_t>(total_points(lengths)));
  for (size_t i = 0; i < lengths.size(); ++i) {
    const Rows r = rows_of(list[i], fmt::format("streamline {}", i), 3);
    if (r.rows != lengths[i])
      throw py::value_error(fmt::format("{}: streamline {} changed length while read", kClass, i));
    copy_points(r, 0, r.rows, to_lps, out.points.data() + out.offsets[i]);
  }
}

// Points given as one (N, 3) array and offsets of count + 1 values.
void copy_offset_points(const py::handle& points, const py::handle& offsets_value,
                        const glm::dmat4& to_lps, Streamlines& out) {
  const Rows r = rows_of(points, "points", 3);
  const std::vector<int64_t> offsets = integers(offsets_value, "offsets");
  if (offsets.empty() || offsets[0] != 0)
    throw py::value_error(
        fmt::format("{}: offsets must start at 0 (count + 1 values: streamline i is "
                    "points[offsets[i]:offsets[i + 1]]), got {}",
                    kClass, offsets.empty() ? std::string("none") : std::to_string(offsets[0])));
  std::vector<int64_t> lengths(offsets.size() - 1);
  for (size_t i = 0; i < lengths.size(); ++i) {
    lengths[i] = offsets[i + 1] - offsets[i];
    if (lengths[i] < 0)
      throw py::value_error(fmt::format("{}: offsets decrease: offsets[{}] = {} after {}", kClass,
                                        i + 1, offsets[i + 1], offsets[i]));
  }
  if (offsets.back() != r.rows)
    throw py::value_error(fmt::format(
        "{}: offsets end at {} but points has {} rows (offsets holds count + 1 values, the last "
        "the number of points)",
        kClass, offsets.back(), r.rows));
  set_offsets(out, lengths);
  out.points.resize(static_cast<size_t>(total_points(lengths)));
  py::gil_scoped_release release;
  copy_points(r, 0, r.rows, to_lps, out.points.data());
}

// Every point a finite position in reach (NaN and inf refused, naming the first).
void check_points(const Streamlines& s) {
  size_t bad = s.points.size();
  for (size_t i = 0; i < s.points.size(); ++i) {
    const glm::vec3& p = s.points[i];
    if (!(std::abs(p.x) <= kMaxCoordinateMm && std::abs(p.y) <= kMaxCoordinateMm &&
          std::abs(p.z) <= kMaxCoordinateMm)) {
      bad = i;
      break;
    }
  }
  if (bad == s.points.size()) return;
  const size_t line =
      static_cast<size_t>(std::upper_bound(s.offsets.begin(), s.offsets.end(), bad) -
                          s.offsets.begin()) -
      1;
  const glm::vec3& p = s.points[bad];
  throw py::value_error(fmt::format(
      "{}: point {} of streamline {} is ({:g}, {:g}, {:g}) (LPS), not a finite position within "
      "{:g} mm of the origin",
      kClass, bad - s.offsets[line], line, p.x, p.y, p.z, kMaxCoordinateMm));
}

glm::dmat4 matrix_of(const py::handle& value, const std::string& what) {
  py::array a = array_argument(value, {kClass, what}, "a 4x4 affine", py::dtype("float64"));
  if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    throw py::value_error(fmt::format("{}: {} must be 4x4, got shape {}", kClass, what,
                                      py::str(a.attr("shape")).cast<std::string>()));
  auto m = py::array_t<double, py::array::forcecast>::ensure(a);
  glm::dmat4 out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      out[c][r] = m.at(r, c);
      if (!std::isfinite(out[c][r]))
        throw py::value_error(fmt::format("{}: {} holds {}", kClass, what, out[c][r]));
    }
  return out;
}

bool is_tractogram(const py::handle& value) {
  return py::hasattr(value, "streamlines") && py::hasattr(value, "data_per_point");
}

// A nibabel Tractogram (or LazyTractogram) or a DIPY StatefulTractogram: its streamlines in RAS
// mm, with its data_per_point and data_per_streamline.
void read_tractogram(const py::handle& tractogram, Streamlines& out,
                     std::vector<std::string>& notes) {
  glm::dmat4 to_ras(1.0);
  if (py::hasattr(tractogram, "affine_to_rasmm")) {
    const py::object affine = tractogram.attr("affine_to_rasmm");
    if (affine.is_none())
      throw py::value_error(fmt::format(
          "{}: the Tractogram's affine_to_rasmm is None, so its space is unknown; give it in RAS "
          "mm (nibabel.streamlines.load gives that)",
          kClass));
    to_ras = matrix_of(affine, "affine_to_rasmm");
  } else if (py::hasattr(tractogram, "space") && py::hasattr(tractogram, "to_rasmm")) {
    const std::string space = py::str(tractogram.attr("space")).cast<std::string>();
    if (space.find("RASMM") == std::string::npos && space != "rasmm")
      throw py::value_error(fmt::format(
          "{}: the StatefulTractogram is in space {}; call sft.to_rasmm() first (intermix reads "
          "RAS mm)",
          kClass, space));
  }
  const glm::dmat4 to_lps = kLpsFromRas * to_ras;
  const py::object streamlines = tractogram.attr("streamlines");
  const bool lazy = !is_array_sequence(streamlines);
  if (lazy)
    copy_list_points(streamlines, to_lps, out);
  else
    copy_sequence_points(sequence_of(streamlines, "streamlines", 3), to_lps, out);
  for (const char* kind : {"data_per_point", "data_per_streamline"}) {
    const py::object data = tractogram.attr(kind);
    if (data.is_none() || py::len(data) == 0) continue;
    if (lazy) {
      notes.push_back(fmt::format("the lazy tractogram's {} was not read", kind));
      continue;
    }
    for (const auto& [name, value] : named_arrays(data, {kClass, kind})) {
      if (std::strcmp(kind, "data_per_point") == 0)
        add_sequence_point_values(out, name, value);
      else
        add_array_values(out.streamline_values, name, value, out.count(), "streamlines",
                         fmt::format("data_per_streamline['{}']", name));
    }
  }
}

// `space` for array sources: RAS (nibabel's and DIPY's world, the default) or LPS.
glm::dmat4 array_space(const py::handle& space_argument) {
  const std::string space = optional_text(space_argument, {kClass, "space"}).value_or("RAS");
  if (space == "RAS" || space == "ras") return kLpsFromRas;
  if (space == "LPS" || space == "lps") return glm::dmat4(1.0);
  throw py::value_error(fmt::format("{}: space '{}' is not RAS or LPS", kClass, space));
}

std::shared_ptr<PyStreamlines> wrap(Streamlines&& s, std::vector<std::string> notes) {
  auto out = std::make_shared<PyStreamlines>();
  out->id = next_source_id("streamlines");
  out->data = std::make_shared<const Streamlines>(std::move(s));
  out->notes = std::move(notes);
  return out;
}

std::shared_ptr<PyStreamlines> load(const py::handle& path_argument, const py::handle& values,
                                    const char* function) {
  const std::filesystem::path file = path(path_argument, {function, "path"});
  std::vector<std::filesystem::path> value_files;
  if (!values.is_none()) {
    if (is_path_like(values)) {
      value_files.push_back(path(values, {function, "values"}));
    } else {
      for (const py::handle v : values) value_files.push_back(path(v, {function, "values"}));
    }
  }
  std::vector<std::string> notes;
  Streamlines s;
  {
    py::gil_scoped_release release;
    s = detail::read_streamline_file(file, value_files, notes);
  }
  return wrap(std::move(s), std::move(notes));
}

std::shared_ptr<PyStreamlines> make_streamlines(const py::object& source,
                                                const OptionalArrayParameter& offsets,
                                                const OptionalTextParameter& space,
                                                const py::object& point_values,
                                                const py::object& streamline_values,
                                                const py::object& values) {
  if (is_path_like(source)) {
    if (!offsets.is_none() || !space.is_none() || !point_values.is_none() ||
        !streamline_values.is_none())
      throw py::value_error(
          fmt::format("{}: a file says its own space and values: offsets, space, point_values and "
                      "streamline_values go with arrays",
                      kClass));
    return load(source, values, kClass);
  }
  if (!values.is_none())
    throw py::value_error(fmt::format("{}: values (.tsf files) go with a file source", kClass));
  Streamlines s;
  std::vector<std::string> notes;
  py::object tractogram = source;
  if (py::hasattr(tractogram, "tractogram") && !is_tractogram(tractogram))
    tractogram = tractogram.attr("tractogram");  // a TrkFile or TckFile
  if (is_tractogram(tractogram)) {
    if (!offsets.is_none() || !space.is_none())
      throw py::value_error(fmt::format(
          "{}: a tractogram says its own layout and space (affine_to_rasmm): offsets and space "
          "go with arrays",
          kClass));
    read_tractogram(tractogram, s, notes);
  } else if (is_array_sequence(source)) {
    if (!offsets.is_none())
      throw py::value_error(fmt::format("{}: an ArraySequence holds its own offsets", kClass));
    copy_sequence_points(sequence_of(source, "source", 3), array_space(space), s);
  } else if (!offsets.is_none()) {
    copy_offset_points(source, offsets, array_space(space), s);
  } else if (PyObject_CheckBuffer(source.ptr()) || py::isinstance<py::str>(source) ||
             !py::isinstance<py::iterable>(source)) {
    throw_wrong_type({kClass, "source"},
                     "a path, a nibabel Tractogram or ArraySequence, a list of (n, 3) arrays, or "
                     "(N, 3) points with offsets",
                     source);
  } else {
    copy_list_points(source, array_space(space), s);
  }
  check_points(s);
  if (!point_values.is_none())
    for (const auto& [name, value] : named_arrays(point_values, {kClass, "point_values"}))
      add_array_values(s.point_values, name, value, s.points.size(), "points",
                       fmt::format("point_values['{}']", name));
  if (!streamline_values.is_none())
    for (const auto& [name, value] : named_arrays(streamline_values, {kClass, "streamline_values"}))
      add_array_values(s.streamline_values, name, value, s.count(), "streamlines",
                       fmt::format("streamline_values['{}']", name));
  return wrap(std::move(s), std::move(notes));
}

py::array float_view(const PyStreamlines& p, const void* data, std::vector<py::ssize_t> shape,
                     const char* dtype = "float32") {
  return view_array(data, py::dtype(dtype), std::move(shape), p.data, false);
}

py::dict values_dict(const PyStreamlines& p, const std::vector<StreamlineValues>& list) {
  py::dict d;
  for (const StreamlineValues& v : list)
    d[py::str(v.name)] =
        float_view(p, v.values.data(), {static_cast<py::ssize_t>(v.values.size())});
  return d;
}

}  // namespace

void bind_streamlines(py::module_& m) {
  py::class_<PyStreamlines, std::shared_ptr<PyStreamlines>>(
      m, "Streamlines",
      R"doc(A tractogram: streamlines in world LPS millimetres, usable as a streamlines object's "source"
in a scene (Scene.add_streamlines, or "source": streamlines in Scene.from_dict).

Streamlines(source, offsets=None, *, space=None, point_values=None, streamline_values=None,
            values=None)
Streamlines.load(path, values=None)

source is one of
  - a file path: TrackVis .trk, MRtrix .tck, TRX, DSI Studio .tt.gz, VTK polylines, read as
    `intermix render` reads them (values: .tsf files of per-point values for a .tck);
  - a nibabel Tractogram, or what nibabel.streamlines.load returns (TrkFile, TckFile): its
    streamlines in RAS mm through affine_to_rasmm, its data_per_point and data_per_streamline
    as values ("rgb[0]".."rgb[2]" for a value of several columns);
  - a DIPY StatefulTractogram in RAS mm (sft.to_rasmm() first);
  - a nibabel ArraySequence (DIPY's Streamlines), or a list of (n, 3) arrays, as DIPY holds
    them;
  - an (N, 3) array of points with `offsets`, count + 1 integers: streamline i is
    points[offsets[i]:offsets[i + 1]].
Arrays are in `space` "RAS" (nibabel's and DIPY's world, the default) or "LPS"; RAS x and y are
negated into LPS. point_values (N rows) and streamline_values (count rows) are dicts of name:
array, rows of one value or several.

Arrays are read through the buffer protocol, float32 and float64 where they lie, with no Python
copy; they are converted once, straight into intermix's own float32 LPS points (the engine's
layout), so later changes to the arrays do not show. Other dtypes are converted by numpy first.
Raises ValueError for shapes or offsets that disagree and for points that are not finite,
OSError when a file cannot be read.
)doc")
      .def(py::init(&make_streamlines), py::arg("source"), py::arg("offsets") = py::none(),
           py::kw_only(), py::arg("space") = py::none(), py::arg("point_values") = py::none(),
           py::arg("streamline_values") = py::none(), py::arg("values") = py::none())
      .def_static(
          "load",
          [](const PathParameter& path, const py::object& values) {
            return load(path, values, "Streamlines.load");
          },
          py::arg("path"), py::arg("values") = py::none(),
          R"doc(Reads a tractogram file (.trk, .tck, .trx, .tt.gz, .vtk/.vtp polylines) through intermix's format
registry, as `intermix render` does; `values` are .tsf files (a path or a list) of per-point
values for a .tck. Streamlines of fewer than two points or with a point that is not finite are
dropped, each with a line in .notes.
)doc")
      .def_property_readonly(
          "count", [](const PyStreamlines& p) { return p.data->count(); },
          "The number of streamlines.")
      .def("__len__", [](const PyStreamlines& p) { return p.data->count(); })
      .def_property_readonly(
          "points",
          [](const PyStreamlines& p) {
            return float_view(p, p.data->points.data(),
                              {static_cast<py::ssize_t>(p.data->points.size()), 3});
          },
          "(N, 3) float32 points of all streamlines, one after another, LPS mm (read-only).")
      .def_property_readonly(
          "offsets",
          [](const PyStreamlines& p) {
            return float_view(p, p.data->offsets.data(),
                              {static_cast<py::ssize_t>(p.data->offsets.size())}, "uint32");
          },
          "(count + 1,) uint32: streamline i is points[offsets[i]:offsets[i + 1]] (read-only).")
      .def_property_readonly(
          "lengths",
          [](const PyStreamlines& p) {
            py::array_t<int64_t> out(static_cast<py::ssize_t>(p.data->count()));
            for (size_t i = 0; i < p.data->count(); ++i)
              out.mutable_at(static_cast<py::ssize_t>(i)) = p.data->length(i);
            return out;
          },
          "(count,) int64 points per streamline (a new array).")
      .def(
          "__getitem__",
          [](const PyStreamlines& p, const IntParameter& index) {
            const auto n = static_cast<long long>(p.data->count());
            long long i = int_in(index, {"Streamlines.__getitem__", "index"}, -n, n - 1);
            if (i < 0) i += n;
            const auto first = static_cast<size_t>(i);
            return float_view(p, p.data->points.data() + p.data->offsets[first],
                              {static_cast<py::ssize_t>(p.data->length(first)), 3});
          },
          py::arg("index"), "Streamline i's (n, 3) float32 points, LPS mm (read-only).")
      .def_property_readonly(
          "point_values",
          [](const PyStreamlines& p) { return values_dict(p, p.data->point_values); },
          "Per-point values by name: (N,) float32 arrays (read-only).")
      .def_property_readonly(
          "streamline_values",
          [](const PyStreamlines& p) { return values_dict(p, p.data->streamline_values); },
          "Per-streamline values by name: (count,) float32 arrays (read-only).")
      .def_property_readonly(
          "value_names",
          [](const PyStreamlines& p) {
            std::vector<std::string> names;
            for (const auto* list : {&p.data->point_values, &p.data->streamline_values})
              for (const StreamlineValues& v : *list) names.push_back(v.name);
            return names;
          },
          "The names Scene.add_streamlines(value=...) takes: per-point values, then "
          "per-streamline ones.")
      .def_property_readonly(
          "groups",
          [](const PyStreamlines& p) {
            std::vector<std::string> names;
            for (const StreamlineGroup& g : p.data->groups) names.push_back(g.name);
            return names;
          },
          "The names of the file's groups (TRX), in order.")
      .def_property_readonly(
          "notes", [](const PyStreamlines& p) { return p.notes; },
          "What reading chose for the user (streamlines dropped, a field missing), one line each.")
      .def("__repr__", [](const PyStreamlines& p) {
        std::string values;
        for (const auto* list : {&p.data->point_values, &p.data->streamline_values})
          for (const StreamlineValues& v : *list)
            values += fmt::format("{}{}", values.empty() ? "; values " : ", ", v.name);
        return fmt::format("<intermix.Streamlines {} streamlines, {} points{}>", p.data->count(),
                           p.data->points.size(), values);
      });
}

}  // namespace imx::python
