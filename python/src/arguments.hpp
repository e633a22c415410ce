// Python arguments as C++ values, with intermix's own messages. Every binding takes its
// parameters as Python objects (the *Parameter types below, which accept anything) and converts
// them here, so a wrong type or value raises TypeError or ValueError naming the function and the
// argument ("Scene.render: width must be an int, got str"), never pybind11's "incompatible
// function arguments"; explain_mismatched_calls does the same for calls that fit no signature.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "bindings.hpp"

namespace imx::python {

// Which argument of which function, as Python spells them: {"Scene.render", "width"}.
struct Argument {
  std::string_view function;
  std::string_view name;
};

// A value's type as messages name it: "str", "None", "numpy.float32", "intermix.Volume".
std::string python_type_name(const py::handle& value);

// TypeError "function: name must be `expected`, got TYPE".
[[noreturn]] void throw_wrong_type(const Argument& argument, std::string_view expected,
                                   const py::handle& value);

// Whether `value` is what int_in takes: a Python int or a numpy integer, not a bool.
bool is_int_like(const py::handle& value);

// An int (a Python int or a numpy integer, through __index__; not a bool, not a float) in
// [lo, hi]; ValueError "function: name V is not in [lo, hi]" otherwise, however large V is.
long long int_in(const py::handle& value, const Argument& argument, long long lo, long long hi);
// The same, None giving nullopt.
std::optional<long long> optional_int_in(const py::handle& value, const Argument& argument,
                                         long long lo, long long hi);
// An int of `lo` or more (sizes in bytes, which have no limit of their own): ValueError
// "function: name is V, not LO or more" below it, "..., more than 2**63 - 1" above a long long.
long long int_at_least(const py::handle& value, const Argument& argument, long long lo);

// A finite real number: an int, a float, a numpy integer or floating scalar, or anything else
// with __float__ (not a bool, not complex). NaN and inf: ValueError "function: name nan is not a
// finite number".
double finite_real(const py::handle& value, const Argument& argument);
// The same, within [lo, hi].
double real_in(const py::handle& value, const Argument& argument, double lo, double hi);
// finite_real, None giving nullopt.
std::optional<double> optional_finite_real(const py::handle& value, const Argument& argument);

// True or False, or a numpy.bool_ (truthy ints and None are refused: linear=1 is a slip).
bool flag(const py::handle& value, const Argument& argument);

// A str, as UTF-8.
std::string text(const py::handle& value, const Argument& argument);
// The same, None giving nullopt.
std::optional<std::string> optional_text(const py::handle& value, const Argument& argument);

// Whether `value` is a str or an os.PathLike (what path() takes, bytes aside).
bool is_path_like(const py::handle& value);
// A file path: a str or an os.PathLike giving one (os.fspath). Bytes are refused (TypeError:
// intermix's paths are text) and so is a NUL character (ValueError: the file name would end
// there).
std::filesystem::path path(const py::handle& value, const Argument& argument);
// The same, None giving nullopt.
std::optional<std::filesystem::path> optional_path(const py::handle& value,
                                                   const Argument& argument);

// numpy.asarray(value, dtype); what numpy refuses (a ragged list, a str as floats) becomes
// TypeError or ValueError "function: name is not `expected`: numpy's reason".
py::array array_argument(const py::handle& value, const Argument& argument,
                         std::string_view expected, const py::handle& dtype = py::none());

// numpy's overflow warning silenced while alive (numpy.errstate(over="ignore")), for a cast to
// float32 whose values past its range intermix's own check names afterwards: the warning, made
// an error by warnings.simplefilter("error"), said only "overflow encountered in cast".
class QuietOverflow {
 public:
  QuietOverflow();
  ~QuietOverflow();
  QuietOverflow(const QuietOverflow&) = delete;
  QuietOverflow& operator=(const QuietOverflow&) = delete;

 private:
  py::object state_;
};

// `given` as C-contiguous float32, converted by numpy (QuietOverflow: the caller checks the
// values). What numpy raises meanwhile is ValueError "what: numpy's reason", a MemoryError stays
// one: array_t::ensure gave an empty array then, read as one (a crash).
py::array_t<float, py::array::c_style | py::array::forcecast> float32_array(
    const py::array& given, const std::string& what);

// A bound class's instance (PyVolume, PyMesh, PyScene), else TypeError "function: name must be
// an intermix.Volume, got str".
template <class T>
T& instance_of(const py::handle& value, const Argument& argument, std::string_view class_name) {
  if (!py::isinstance<T>(value)) throw_wrong_type(argument, class_name, value);
  return value.cast<T&>();
}

// Makes every pybind11 function of `module` and its classes raise intermix's own TypeError
// when a call fits no signature: an unknown keyword (with the closest known one and the
// accepted ones), too many positional arguments, a missing or doubled argument, a self of
// another type. Call it after the last binding.
void explain_mismatched_calls(py::module_& module);

// The *Parameter types' check: every object passes, for the binding's body to convert.
inline int parameter_accepts(PyObject* /*value*/) {
  return 1;
}

}  // namespace imx::python

// A parameter type that takes any object, for the body to convert, and shows as `shown` in
// help(): pybind11 never refuses the call, so the conversion's message is the one raised.
#define IMX_PYTHON_PARAMETER(Name, shown)                                       \
  namespace imx::python {                                                       \
  class Name : public py::object {                                              \
   public:                                                                      \
    PYBIND11_OBJECT_DEFAULT(Name, py::object, ::imx::python::parameter_accepts) \
  };                                                                            \
  }                                                                             \
  template <>                                                                   \
  struct pybind11::detail::handle_type_name<imx::python::Name> {                \
    static constexpr auto name = pybind11::detail::const_name(shown);           \
  };

IMX_PYTHON_PARAMETER(IntParameter, "int")
IMX_PYTHON_PARAMETER(OptionalIntParameter, "Optional[int]")
IMX_PYTHON_PARAMETER(RealParameter, "float")
IMX_PYTHON_PARAMETER(OptionalRealParameter, "Optional[float]")
IMX_PYTHON_PARAMETER(FlagParameter, "bool")
IMX_PYTHON_PARAMETER(TextParameter, "str")
IMX_PYTHON_PARAMETER(OptionalTextParameter, "Optional[str]")
IMX_PYTHON_PARAMETER(PathParameter, "Union[str, os.PathLike]")
IMX_PYTHON_PARAMETER(OptionalPathParameter, "Optional[Union[str, os.PathLike]]")
IMX_PYTHON_PARAMETER(SeriesParameter, "Union[str, int, None]")
IMX_PYTHON_PARAMETER(ArrayParameter, "ArrayLike")
IMX_PYTHON_PARAMETER(OptionalArrayParameter, "Optional[ArrayLike]")
IMX_PYTHON_PARAMETER(ImageParameter, "Union[ArrayLike, str, os.PathLike]")
IMX_PYTHON_PARAMETER(VolumeParameter, "intermix.Volume")
IMX_PYTHON_PARAMETER(SceneParameter, "intermix.Scene")
IMX_PYTHON_PARAMETER(SceneDictParameter, "Mapping[str, Any]")
IMX_PYTHON_PARAMETER(VolumeSourceParameter,
                     "Union[intermix.Volume, ArrayLike, str, os.PathLike, Mapping[str, Any]]")
IMX_PYTHON_PARAMETER(MeshSourceParameter,
                     "Union[intermix.Mesh, str, os.PathLike, Mapping[str, Any]]")
IMX_PYTHON_PARAMETER(SceneValueParameter, "Any")

#undef IMX_PYTHON_PARAMETER
