// Python arguments as C++ values with intermix's own messages (arguments.hpp).
#include "arguments.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <fmt/format.h>

namespace imx::python {
namespace {

py::module_ numpy() {
  return py::module_::import("numpy");
}

bool is_numpy_instance(const py::handle& value, const char* numpy_type) {
  return py::isinstance(value, numpy().attr(numpy_type));
}

bool is_any_bool(const py::handle& value) {
  return PyBool_Check(value.ptr()) ||
         (!PyLong_Check(value.ptr()) && is_numpy_instance(value, "bool_"));
}

std::string prefix(const Argument& argument) {
  return fmt::format("{}: {}", argument.function, argument.name);
}

// The digits of an int, or its magnitude when they would fill the screen ("about -1e90").
std::string int_text(const py::handle& integer) {
  const auto bits = integer.attr("bit_length")().cast<long long>();
  if (bits <= 256) return py::str(integer).cast<std::string>();
  const bool negative = PyObject_RichCompareBool(integer.ptr(), py::int_(0).ptr(), Py_LT) == 1;
  const auto digits = static_cast<long long>(static_cast<double>(bits - 1) * std::log10(2.0));
  return fmt::format("about {}1e{}", negative ? "-" : "", digits);
}

// The Python int that `value` stands for: an int or a numpy integer, never a bool.
py::int_ index_of(const py::handle& value, const Argument& argument) {
  if (PyLong_Check(value.ptr()) && !PyBool_Check(value.ptr()))
    return py::reinterpret_borrow<py::int_>(value);
  if (!PyIndex_Check(value.ptr()) || is_any_bool(value))
    throw_wrong_type(argument, "an int", value);
  PyObject* index = PyNumber_Index(value.ptr());
  if (index == nullptr) {
    PyErr_Clear();  // an __index__ that raised: the value is no int after all
    throw_wrong_type(argument, "an int", value);
  }
  return py::reinterpret_steal<py::int_>(index);
}

// `value` as a long long, or nullopt beyond its range.
std::optional<long long> long_long_of(const py::int_& value) {
  int overflow = 0;
  const long long result = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
  if (overflow != 0) return std::nullopt;
  return result;
}

double real_of(const py::handle& value, const Argument& argument) {
  PyObject* p = value.ptr();
  const bool numeric = PyFloat_Check(p) || PyLong_Check(p) || PyIndex_Check(p) ||
                       (Py_TYPE(p)->tp_as_number && Py_TYPE(p)->tp_as_number->nb_float);
  if (!numeric || is_any_bool(value) || PyComplex_Check(p) ||
      is_numpy_instance(value, "complexfloating"))
    throw_wrong_type(argument, "a real number", value);
  const double result = PyFloat_AsDouble(p);
  if (result == -1.0 && PyErr_Occurred()) {
    const bool too_large = PyErr_ExceptionMatches(PyExc_OverflowError);
    PyErr_Clear();
    if (!too_large) throw_wrong_type(argument, "a real number", value);
    const std::string shown = PyIndex_Check(p) ? int_text(index_of(value, argument))
                                               : py::repr(value).cast<std::string>();
    throw py::value_error(fmt::format("{} {} is beyond the range of a number (about 1.8e308)",
                                      prefix(argument), shown));
  }
  return result;
}

// Text as UTF-8, or ValueError for a str that has none (lone surrogates).
std::string utf8_of(const py::handle& value, const Argument& argument) {
  Py_ssize_t size = 0;
  const char* data = PyUnicode_AsUTF8AndSize(value.ptr(), &size);
  if (data == nullptr) {
    PyErr_Clear();
    throw py::value_error(
        fmt::format("{} is not valid text (it holds lone surrogates)", prefix(argument)));
  }
  return std::string(data, static_cast<size_t>(size));
}

}  // namespace

bool is_int_like(const py::handle& value) {
  return PyIndex_Check(value.ptr()) && !is_any_bool(value);
}

std::string python_type_name(const py::handle& value) {
  if (value.is_none()) return "None";
  const py::handle type = reinterpret_cast<PyObject*>(Py_TYPE(value.ptr()));
  const std::string name = py::str(type.attr("__qualname__")).cast<std::string>();
  const py::object module = py::getattr(type, "__module__", py::none());
  if (!py::isinstance<py::str>(module)) return name;
  std::string module_name = module.cast<std::string>();
  if (module_name == "builtins") return name;
  if (module_name == "intermix._intermix") module_name = "intermix";  // before __init__ renames
  return module_name + "." + name;
}

void throw_wrong_type(const Argument& argument, std::string_view expected,
                      const py::handle& value) {
  throw py::type_error(
      fmt::format("{} must be {}, got {}", prefix(argument), expected, python_type_name(value)));
}

long long int_in(const py::handle& value, const Argument& argument, long long lo, long long hi) {
  const py::int_ index = index_of(value, argument);
  const std::optional<long long> result = long_long_of(index);
  if (!result || *result < lo || *result > hi)
    throw py::value_error(
        fmt::format("{} {} is not in [{}, {}]", prefix(argument), int_text(index), lo, hi));
  return *result;
}

std::optional<long long> optional_int_in(const py::handle& value, const Argument& argument,
                                         long long lo, long long hi) {
  if (value.is_none()) return std::nullopt;
  return int_in(value, argument, lo, hi);
}

long long int_at_least(const py::handle& value, const Argument& argument, long long lo) {
  const py::int_ index = index_of(value, argument);
  const std::optional<long long> result = long_long_of(index);
  if (result && *result >= lo) return *result;
  if (!result && PyObject_RichCompareBool(index.ptr(), py::int_(0).ptr(), Py_GT) == 1)
    throw py::value_error(fmt::format("{} is {}, more than {}", prefix(argument), int_text(index),
                                      std::numeric_limits<long long>::max()));
  throw py::value_error(
      fmt::format("{} is {}, not {} or more", prefix(argument), int_text(index), lo));
}

double finite_real(const py::handle& value, const Argument& argument) {
  const double result = real_of(value, argument);
  if (!std::isfinite(result))
    throw py::value_error(fmt::format("{} {} is not a finite number", prefix(argument), result));
  return result;
}

double real_in(const py::handle& value, const Argument& argument, double lo, double hi) {
  const double result = finite_real(value, argument);
  if (result < lo || result > hi)
    throw py::value_error(
        fmt::format("{} {:g} is not in [{:g}, {:g}]", prefix(argument), result, lo, hi));
  return result;
}

std::optional<double> optional_finite_real(const py::handle& value, const Argument& argument) {
  if (value.is_none()) return std::nullopt;
  return finite_real(value, argument);
}

bool flag(const py::handle& value, const Argument& argument) {
  if (PyBool_Check(value.ptr())) return value.ptr() == Py_True;
  if (!PyLong_Check(value.ptr()) && is_numpy_instance(value, "bool_"))
    return PyObject_IsTrue(value.ptr()) == 1;
  throw_wrong_type(argument, "a bool (True or False)", value);
}

std::string text(const py::handle& value, const Argument& argument) {
  if (!PyUnicode_Check(value.ptr())) throw_wrong_type(argument, "a str", value);
  return utf8_of(value, argument);
}

std::optional<std::string> optional_text(const py::handle& value, const Argument& argument) {
  if (value.is_none()) return std::nullopt;
  return text(value, argument);
}

bool is_path_like(const py::handle& value) {
  return PyUnicode_Check(value.ptr()) ||
         py::isinstance(value, py::module_::import("os").attr("PathLike"));
}

std::filesystem::path path(const py::handle& value, const Argument& argument) {
  constexpr const char* kExpected = "a path (a str or an os.PathLike)";
  if (PyBytes_Check(value.ptr()) || PyByteArray_Check(value.ptr()))
    throw py::type_error(fmt::format("{} must be {}, got {}; decode bytes paths with os.fsdecode",
                                     prefix(argument), kExpected, python_type_name(value)));
  if (!is_path_like(value)) throw_wrong_type(argument, kExpected, value);
  py::object given;
  try {
    given = py::module_::import("os").attr("fspath")(value);
  } catch (const py::error_already_set& e) {
    // e.what() ends in pybind11's traceback ("\n\nAt:\n ..."): the exception's own line only.
    const std::string reason = py::str(e.value()).cast<std::string>();
    throw py::type_error(fmt::format("{}: os.fspath failed on the {}: {}: {}", prefix(argument),
                                     python_type_name(value),
                                     py::str(e.type().attr("__qualname__")).cast<std::string>(),
                                     reason.substr(0, reason.find('\n'))));
  }
  if (!PyUnicode_Check(given.ptr()))
    throw py::type_error(fmt::format("{} must be {}, got a {} whose path is {}", prefix(argument),
                                     kExpected, python_type_name(value), python_type_name(given)));
  // The file system's bytes: a name os.fsdecode made of bytes that are not UTF-8 comes back.
  PyObject* encoded = PyUnicode_EncodeFSDefault(given.ptr());
  if (encoded == nullptr) {
    PyErr_Clear();
    throw py::value_error(fmt::format("{} cannot be encoded as a file name", prefix(argument)));
  }
  const py::bytes bytes = py::reinterpret_steal<py::bytes>(encoded);
  std::string name = bytes;
  if (name.find('\0') != std::string::npos)
    throw py::value_error(fmt::format("{} holds a NUL character", prefix(argument)));
  return name;
}

std::optional<std::filesystem::path> optional_path(const py::handle& value,
                                                   const Argument& argument) {
  if (value.is_none()) return std::nullopt;
  return path(value, argument);
}

py::array array_argument(const py::handle& value, const Argument& argument,
                         std::string_view expected, const py::handle& dtype) {
  try {
    return numpy().attr("asarray")(value, py::arg("dtype") = dtype);
  } catch (py::error_already_set& e) {
    const std::string reason = py::str(e.value()).cast<std::string>();
    const std::string message = fmt::format("{} is not {}: {}", prefix(argument), expected,
                                            reason.substr(0, reason.find('\n')));
    if (e.matches(PyExc_TypeError)) throw py::type_error(message);
    if (e.matches(PyExc_MemoryError)) throw;
    throw py::value_error(message);
  }
}

QuietOverflow::QuietOverflow() : state_(numpy().attr("errstate")(py::arg("over") = "ignore")) {
  state_.attr("__enter__")();
}

QuietOverflow::~QuietOverflow() {
  try {
    state_.attr("__exit__")(py::none(), py::none(), py::none());
  } catch (py::error_already_set&) {
    PyErr_Clear();  // restoring numpy's error state cannot fail in a way worth a crash
  }
}

py::array_t<float, py::array::c_style | py::array::forcecast> float32_array(
    const py::array& given, const std::string& what) {
  using Floats = py::array_t<float, py::array::c_style | py::array::forcecast>;
  const QuietOverflow quiet;
  try {
    return numpy().attr("ascontiguousarray")(given, py::arg("dtype") = "float32").cast<Floats>();
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_MemoryError)) throw;
    const std::string reason = py::str(e.value()).cast<std::string>();
    throw py::value_error(fmt::format("{}: {}", what, reason.substr(0, reason.find('\n'))));
  }
}

}  // namespace imx::python
