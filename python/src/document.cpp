// Scene documents from Python values and back (document.hpp).
#include "document.hpp"

#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "scene/strict_json.hpp"

namespace imx::python {
namespace {

constexpr const char* kVolumeKey = "$volume";
constexpr const char* kMeshKey = "$mesh";
constexpr const char* kStreamlinesKey = "$streamlines";
// The most values a numpy array in a scene document may hold (transfer-function points, colour
// tables): voxels and vertices go through Volume and Mesh, not through JSON.
constexpr py::ssize_t kMaxArrayValues = py::ssize_t{1} << 18;

[[noreturn]] void fail(const std::string& origin, const std::string& path,
                       const std::string& message) {
  throw py::value_error(path.empty() ? fmt::format("{}: {}", origin, message)
                                     : fmt::format("{}: {}: {}", origin, path, message));
}

std::string type_name(const py::handle& value) {
  return py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>();
}

// A str as UTF-8. One holding lone surrogates (os.fsdecode's for bytes that are not UTF-8) is
// refused, naming where it is: pybind11's cast said only "Unable to cast Python instance".
std::string utf8_text(const py::handle& value, const std::string& origin, const std::string& path,
                      const char* what) {
  Py_ssize_t size = 0;
  const char* data = PyUnicode_AsUTF8AndSize(value.ptr(), &size);
  if (data == nullptr) {
    PyErr_Clear();
    fail(origin, path,
         fmt::format("{}{} is not valid text (it holds lone surrogates)", what,
                     py::repr(value).cast<std::string>()));
  }
  return std::string(data, static_cast<size_t>(size));
}

// A numpy floating scalar that has no Python type (longdouble: its tolist() gives itself back,
// which recursed until the stack ran out) as a double, or refused when a double cannot hold it.
double numpy_scalar_real(const py::handle& value, const std::string& origin,
                         const std::string& path) {
  const py::module_ np = py::module_::import("numpy");
  if (!py::isinstance(value, np.attr("floating")))
    fail(origin, path,
         fmt::format("a numpy.{} is not a scene value (dict, list, str, number, bool, None, numpy "
                     "array, intermix.Volume, intermix.Mesh or intermix.Streamlines)",
                     type_name(value)));
  const double d = PyFloat_AsDouble(value.ptr());
  if (d == -1.0 && PyErr_Occurred()) throw py::error_already_set();
  if (std::isfinite(d)) return d;
  const std::string shown = py::str(value).cast<std::string>();
  if (np.attr("isfinite")(value).cast<bool>())
    fail(origin, path,
         fmt::format("{} is too large: numbers are used as floats (at most {:g})", shown,
                     static_cast<double>(std::numeric_limits<float>::max())));
  fail(origin, path, fmt::format("{} is not a finite number", shown));
}

nlohmann::json convert(const py::handle& value, GivenSources& sources, const std::string& origin,
                       const std::string& path, int depth) {
  if (depth > scene_json::kMaxJsonDepth)
    fail(origin, path, fmt::format("nested deeper than {} levels", scene_json::kMaxJsonDepth));
  if (value.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) {
    // Integers beyond 64 bits become numbers, as JSON text would read them.
    try {
      return value.cast<long long>();
    } catch (const py::cast_error&) {
    }
    try {
      return value.cast<unsigned long long>();
    } catch (const py::cast_error&) {
    }
    const double d = PyLong_AsDouble(value.ptr());
    if (d == -1.0 && PyErr_Occurred()) {
      // Past a double's range: Python's "int too large to convert to float" named nothing.
      PyErr_Clear();
      const std::string digits = py::str(value).cast<std::string>();
      fail(origin, path,
           fmt::format("an int of {} digits is too large: numbers are used as floats (at most "
                       "{:g})",
                       digits.size() - (digits.front() == '-' ? 1 : 0),
                       static_cast<double>(std::numeric_limits<float>::max())));
    }
    return d;
  }
  if (py::isinstance<py::float_>(value)) {
    const double d = value.cast<double>();
    if (!std::isfinite(d)) fail(origin, path, fmt::format("{} is not a finite number", d));
    return d;
  }
  if (py::isinstance<py::str>(value)) return utf8_text(value, origin, path, "");
  if (py::isinstance<PyVolume>(value)) {
    const std::string& id = value.cast<const PyVolume&>().id;
    sources[id] = py::reinterpret_borrow<py::object>(value);
    return {{kVolumeKey, id}};
  }
  if (py::isinstance<PyMesh>(value)) {
    const std::string& id = value.cast<const PyMesh&>().id;
    sources[id] = py::reinterpret_borrow<py::object>(value);
    return {{kMeshKey, id}};
  }
  if (py::isinstance<PyStreamlines>(value)) {
    const std::string& id = value.cast<const PyStreamlines&>().id;
    sources[id] = py::reinterpret_borrow<py::object>(value);
    return {{kStreamlinesKey, id}};
  }
  if (py::isinstance<py::dict>(value) ||
      py::isinstance(value, py::module_::import("collections.abc").attr("Mapping"))) {
    nlohmann::json object = nlohmann::json::object();
    py::object items = value.attr("items")();
    for (const py::handle item : items) {
      py::tuple kv = py::reinterpret_borrow<py::tuple>(item);
      if (!py::isinstance<py::str>(kv[0]))
        fail(origin, path,
             fmt::format("key {} is a {}; keys must be strings",
                         py::repr(kv[0]).cast<std::string>(), type_name(kv[0])));
      const std::string key = utf8_text(kv[0], origin, path, "key ");
      // Checked before anything converts the array: turning a volume into JSON to print an
      // error took seconds and hundreds of MiB.
      if (key == "source" && py::isinstance<py::array>(kv[1]))
        fail(origin, path.empty() ? key : path + "." + key,
             fmt::format("a numpy array of shape {} is not a source: wrap it as "
                         "intermix.Volume(array, affine, axes=...), or add it with "
                         "scene.add_volume(name, array, affine)",
                         py::str(kv[1].attr("shape")).cast<std::string>()));
      object[key] =
          convert(kv[1], sources, origin, path.empty() ? key : path + "." + key, depth + 1);
    }
    return object;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    nlohmann::json array = nlohmann::json::array();
    size_t i = 0;
    for (const py::handle element : value)
      array.push_back(
          convert(element, sources, origin, fmt::format("{}[{}]", path, i++), depth + 1));
    return array;
  }
  py::module_ np = py::module_::import("numpy");
  if (py::isinstance<py::array>(value) &&
      py::reinterpret_borrow<py::array>(value).size() > kMaxArrayValues)
    fail(origin, path,
         fmt::format("a numpy array of shape {} ({} values) is too large for a scene value (at "
                     "most {}); volumes are intermix.Volume objects (scene.add_volume), meshes "
                     "intermix.Mesh",
                     py::str(value.attr("shape")).cast<std::string>(),
                     py::reinterpret_borrow<py::array>(value).size(), kMaxArrayValues));
  if (py::isinstance(value, np.attr("ndarray")) || py::isinstance(value, np.attr("generic"))) {
    const py::object plain = value.attr("tolist")();
    if (py::isinstance(plain, np.attr("generic"))) return numpy_scalar_real(plain, origin, path);
    return convert(plain, sources, origin, path, depth + 1);
  }
  if (py::isinstance(value, py::module_::import("os").attr("PathLike"))) {
    const py::object given = py::module_::import("os").attr("fspath")(value);
    if (!py::isinstance<py::str>(given))
      fail(origin, path,
           fmt::format("a {} whose path is {} is not a scene value (paths are text)",
                       type_name(value), type_name(given)));
    return utf8_text(given, origin, path, "");
  }
  fail(origin, path,
       fmt::format("a {} is not a scene value (dict, list, str, number, bool, None, numpy "
                   "array, intermix.Volume, intermix.Mesh or intermix.Streamlines)",
                   type_name(value)));
}

// The id a placeholder object names, or nullptr.
const std::string* placeholder(const nlohmann::json& j) {
  if (!j.is_object() || j.size() != 1) return nullptr;
  for (const char* key : {kVolumeKey, kMeshKey, kStreamlinesKey}) {
    auto it = j.find(key);
    if (it != j.end() && it->is_string()) return it->get_ptr<const std::string*>();
  }
  return nullptr;
}

void collect_ids(const nlohmann::json& j, std::set<std::string>& ids) {
  if (const std::string* id = placeholder(j)) {
    ids.insert(*id);
  } else if (j.is_structured()) {
    for (const nlohmann::json& child : j) collect_ids(child, ids);
  }
}

}  // namespace

nlohmann::json to_document(const py::handle& value, GivenSources& sources,
                           const std::string& origin, const std::string& path) {
  return convert(value, sources, origin, path, 0);
}

py::object from_document(const nlohmann::json& j, const GivenSources& sources) {
  switch (j.type()) {
    case nlohmann::json::value_t::null:
      return py::none();
    case nlohmann::json::value_t::boolean:
      return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer:
      return py::int_(j.get<long long>());
    case nlohmann::json::value_t::number_unsigned:
      return py::int_(j.get<unsigned long long>());
    case nlohmann::json::value_t::number_float:
      return py::float_(j.get<double>());
    case nlohmann::json::value_t::string:
      return py::str(j.get_ref<const std::string&>());
    case nlohmann::json::value_t::array: {
      py::list list;
      for (const nlohmann::json& element : j) list.append(from_document(element, sources));
      return list;
    }
    case nlohmann::json::value_t::object: {
      if (const std::string* id = placeholder(j))
        if (auto it = sources.find(*id); it != sources.end()) return it->second;
      py::dict dict;
      for (const auto& [key, element] : j.items())
        dict[py::str(key)] = from_document(element, sources);
      return dict;
    }
    default:
      return py::none();  // binary and discarded values never occur in a scene
  }
}

void keep_named_sources(const nlohmann::json& document, GivenSources& sources) {
  std::set<std::string> ids;
  collect_ids(document, ids);
  for (auto it = sources.begin(); it != sources.end();)
    it = ids.count(it->first) ? std::next(it) : sources.erase(it);
}

}  // namespace imx::python
