// Calls that fit no signature (arguments.hpp's explain_mismatched_calls): every binding's calls
// go through one dispatcher, which gives intermix's own TypeError for a call pybind11 refuses,
// refuses instances made without __init__, and gives classes without a constructor their own.
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "arguments.hpp"
#include "core/edit_distance.hpp"

namespace imx::python {

namespace {

using FunctionRecord = py::detail::function_record;

// pybind11's dispatcher, which every function of the module shares (its PyMethodDef's ml_meth).
PyCFunctionWithKeywords pybind11_dispatcher = nullptr;

std::string quoted_list(const std::vector<std::string>& names) {
  std::vector<std::string> quoted;
  for (const std::string& name : names) quoted.push_back("'" + name + "'");
  return fmt::format("{}", fmt::join(quoted, ", "));
}

// How Python spells the function: "phantom", "Scene.render", "Volume" (its constructor), "a
// Volume property" (properties' functions have no name of their own).
std::string function_name(const FunctionRecord& record) {
  const std::string name = record.name ? record.name : "";
  if (!record.scope || !PyType_Check(record.scope.ptr())) return name;
  const std::string type = py::str(record.scope.attr("__name__")).cast<std::string>();
  if (name.empty()) return "a " + type + " property";
  return name == "__init__" ? type : type + "." + name;
}

// The parameters a caller names: every one but self.
struct Parameters {
  std::vector<std::string> names;
  std::vector<py::handle> defaults;  // null where there is none
  size_t positional = 0;             // the first `positional` may be given by position
  bool takes_keywords = false;       // **kwargs takes any other keyword
};

Parameters parameters_of(const FunctionRecord& record) {
  Parameters p;
  const size_t self = record.is_method ? 1 : 0;
  const size_t count = record.nargs - (record.has_args ? 1 : 0) - (record.has_kwargs ? 1 : 0);
  for (size_t i = self; i < count; ++i) {
    const bool known = i < record.args.size() && record.args[i].name != nullptr;
    p.names.push_back(known ? record.args[i].name : fmt::format("arg{}", i - self));
    p.defaults.push_back(i < record.args.size() ? record.args[i].value : py::handle());
  }
  p.positional = record.nargs_pos > self ? record.nargs_pos - self : 0;
  p.takes_keywords = record.has_kwargs;
  return p;
}

// "(path, *, space='LPS', frame=0)": the signature as Python writes it.
std::string signature_of(const Parameters& p) {
  std::vector<std::string> parts;
  for (size_t i = 0; i < p.names.size(); ++i) {
    if (i == p.positional) parts.emplace_back("*");
    parts.push_back(p.defaults[i] ? p.names[i] + "=" + py::repr(p.defaults[i]).cast<std::string>()
                                  : p.names[i]);
  }
  if (p.takes_keywords) parts.emplace_back("**keys");
  return fmt::format("({})", fmt::join(parts, ", "));
}

// What is wrong with a call pybind11 found no overload for, in Python's words.
std::string describe_mismatch(const FunctionRecord& record, PyObject* args, PyObject* kwargs) {
  const std::string function = function_name(record);
  const Parameters p = parameters_of(record);
  const std::string takes = "; it takes " + signature_of(p);
  const auto given = static_cast<size_t>(PyTuple_GET_SIZE(args));
  const size_t self = record.is_method ? 1 : 0;
  if (record.is_method && !record.is_constructor) {
    const std::string type = py::str(record.scope.attr("__name__")).cast<std::string>();
    if (given == 0)
      return fmt::format("{}: called without an intermix.{} (call it on one)", function, type);
    const py::handle first = PyTuple_GET_ITEM(args, 0);
    if (PyObject_IsInstance(first.ptr(), record.scope.ptr()) != 1) {
      PyErr_Clear();
      return fmt::format("{}: self must be an intermix.{}, got {}", function, type,
                         python_type_name(first));
    }
  }
  const size_t positional = given - std::min(given, self);
  if (!record.has_args && positional > p.positional) {
    const std::vector<std::string> names(p.names.begin(), p.names.begin() + p.positional);
    const std::string by_position =
        p.positional == 0 ? "takes no positional arguments"
                          : fmt::format("takes at most {} positional argument{} ({})", p.positional,
                                        p.positional == 1 ? "" : "s", fmt::join(names, ", "));
    return fmt::format("{}: {}, got {}{}", function, by_position, positional, takes);
  }
  std::vector<std::string> named;
  if (kwargs != nullptr) {
    PyObject *key = nullptr, *value = nullptr;
    Py_ssize_t pos = 0;
    while (PyDict_Next(kwargs, &pos, &key, &value)) {
      const std::string name = py::str(key).cast<std::string>();
      named.push_back(name);
      const auto it = std::find(p.names.begin(), p.names.end(), name);
      if (it == p.names.end()) {
        if (p.takes_keywords) continue;
        return fmt::format("{}: got an unexpected keyword argument '{}'{}{}", function, name,
                           imx::did_you_mean(name, p.names), takes);
      }
      if (static_cast<size_t>(it - p.names.begin()) < positional)
        return fmt::format("{}: got '{}' twice, by position and by keyword{}", function, name,
                           takes);
    }
  }
  std::vector<std::string> missing;
  for (size_t i = positional; i < p.names.size(); ++i)
    if (!p.defaults[i] && std::find(named.begin(), named.end(), p.names[i]) == named.end())
      missing.push_back(p.names[i]);
  if (!missing.empty())
    return fmt::format("{}: missing the argument{} {}{}", function, missing.size() == 1 ? "" : "s",
                       quoted_list(missing), takes);
  return fmt::format("{}: cannot take these arguments{}", function, takes);
}

// Replaces pybind11's "NAME(): incompatible function arguments ..." TypeError, which is set,
// by intermix's own; any other error stays as it is.
void replace_mismatch_error(PyObject* capsule, PyObject* args, PyObject* kwargs) {
  PyObject *type = nullptr, *value = nullptr, *trace = nullptr;
  PyErr_Fetch(&type, &value, &trace);
  std::string message;
  try {
    const auto* record = static_cast<const FunctionRecord*>(
        PyCapsule_GetPointer(capsule, py::detail::get_function_record_capsule_name()));
    if (record == nullptr) throw py::error_already_set();
    const std::string text = value ? py::str(value).cast<std::string>() : std::string();
    const std::string expected =
        std::string(record->name ? record->name : "") + "(): incompatible ";
    if (text.compare(0, expected.size(), expected) == 0)
      message = describe_mismatch(*record, args, kwargs);
  } catch (...) {
    PyErr_Clear();  // describing failed: pybind11's message is better than none
    message.clear();
  }
  if (message.empty()) {
    PyErr_Restore(type, value, trace);
    return;
  }
  Py_XDECREF(type);
  Py_XDECREF(value);
  Py_XDECREF(trace);
  PyErr_SetString(PyExc_TypeError, message.c_str());
}

// Whether `value` is an instance of a bound class made by Cls.__new__ without __init__: it
// holds no C++ object, and a method reading it crashed (Volume.__new__(Volume).shape).
bool unready_instance(PyObject* value) {
  if (!PyObject_TypeCheck(
          value, reinterpret_cast<PyTypeObject*>(py::detail::get_internals().instance_base)))
    return false;
  auto* inst = reinterpret_cast<py::detail::instance*>(value);
  for (const py::detail::value_and_holder& vh : py::detail::values_and_holders(inst))
    if (!vh.holder_constructed()) return true;
  return false;
}

// True, with TypeError set, when an argument of the call (self among them, but for __init__,
// which makes it) is such an instance.
bool refused_unready_argument(PyObject* capsule, PyObject* args, PyObject* kwargs) {
  const auto* record = static_cast<const FunctionRecord*>(
      PyCapsule_GetPointer(capsule, py::detail::get_function_record_capsule_name()));
  if (record == nullptr) {
    PyErr_Clear();
    return false;
  }
  const bool constructor =
      record->is_constructor || (record->name && std::strcmp(record->name, "__init__") == 0);
  std::vector<PyObject*> given;
  for (Py_ssize_t i = constructor ? 1 : 0; args && i < PyTuple_GET_SIZE(args); ++i)
    given.push_back(PyTuple_GET_ITEM(args, i));
  PyObject *key = nullptr, *value = nullptr;
  for (Py_ssize_t at = 0; kwargs && PyDict_Next(kwargs, &at, &key, &value);) given.push_back(value);
  for (PyObject* v : given)
    if (unready_instance(v)) {
      // "Scene.to_dict", "write_volume", or the class alone for a property's getter.
      std::string function = record->name ? record->name : "";
      if (record->scope && PyType_Check(record->scope.ptr()))
        function = reinterpret_cast<PyTypeObject*>(record->scope.ptr())->tp_name +
                   (function.empty() ? "" : "." + function);
      const std::string name = Py_TYPE(v)->tp_name;
      PyErr_SetString(PyExc_TypeError,
                      fmt::format("{}: a {} made by {}.__new__ and never initialized; make one "
                                  "with intermix.{}(...) or the function that gives one",
                                  function, name, name, name)
                          .c_str());
      return true;
    }
  return false;
}

PyObject* dispatch_with_own_errors(PyObject* capsule, PyObject* args, PyObject* kwargs) {
  if (refused_unready_argument(capsule, args, kwargs)) return nullptr;
  PyObject* result = pybind11_dispatcher(capsule, args, kwargs);
  if (result == nullptr && PyErr_ExceptionMatches(PyExc_TypeError))
    replace_mismatch_error(capsule, args, kwargs);
  return result;
}

// Routes a pybind11 function's calls through dispatch_with_own_errors (its PyMethodDef is its
// own, so no other function changes); anything else is left alone.
void route_through_own_errors(const py::handle& function) {
  if (!function || !PyCFunction_Check(function.ptr())) return;
  auto* cfunction = reinterpret_cast<PyCFunctionObject*>(function.ptr());
  if (cfunction->m_self == nullptr || !PyCapsule_CheckExact(cfunction->m_self)) return;
  if (!py::detail::is_function_record_capsule(
          py::reinterpret_borrow<py::capsule>(cfunction->m_self)))
    return;
  PyMethodDef* def = cfunction->m_ml;
  if ((def->ml_flags & METH_KEYWORDS) == 0) return;
  auto* current =
      reinterpret_cast<PyCFunctionWithKeywords>(reinterpret_cast<void (*)()>(def->ml_meth));
  if (current == &dispatch_with_own_errors) return;
  if (pybind11_dispatcher == nullptr) pybind11_dispatcher = current;
  if (current != pybind11_dispatcher) return;
  def->ml_meth =
      reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(&dispatch_with_own_errors));
}

// The functions behind a class attribute: a method's, a static method's, a property's getter
// and setter, or the attribute itself.
std::vector<py::object> functions_behind(const py::handle& attribute) {
  if (PyInstanceMethod_Check(attribute.ptr()))
    return {py::reinterpret_borrow<py::object>(PyInstanceMethod_GET_FUNCTION(attribute.ptr()))};
  const py::module_ builtins = py::module_::import("builtins");
  if (py::isinstance(attribute, builtins.attr("staticmethod"))) return {attribute.attr("__func__")};
  if (py::isinstance(attribute, builtins.attr("property")))
    return {attribute.attr("fget"), attribute.attr("fset")};
  return {py::reinterpret_borrow<py::object>(attribute)};
}

// Gives a class that has no constructor (one only intermix makes: View, RendererStats) an
// __init__ raising intermix's own TypeError: pybind11's said "intermix._intermix.View: No
// constructor defined!", naming the C++ module.
void refuse_construction(const py::handle& cls) {
  const std::string name = "intermix." + py::str(cls.attr("__name__")).cast<std::string>();
  py::setattr(cls, "__init__",
              py::cpp_function(
                  [name](const py::handle&, const py::args&, const py::kwargs&) {
                    throw py::type_error(fmt::format(
                        "{} is not made directly: intermix gives one (see help({}))", name, name));
                  },
                  py::is_method(cls)));
}

}  // namespace

void explain_mismatched_calls(py::module_& module) {
  const py::object module_name = module.attr("__name__");
  for (const auto item : py::reinterpret_borrow<py::dict>(module.attr("__dict__"))) {
    const py::handle value = item.second;
    route_through_own_errors(value);
    if (!PyType_Check(value.ptr()) ||
        !py::getattr(value, "__module__", py::none()).equal(module_name))
      continue;
    // tp_dict, not __dict__: a class's __dict__ is a read-only proxy.
    const auto* type = reinterpret_cast<PyTypeObject*>(value.ptr());
    // Without a py::init the type's __init__ is pybind11's slot wrapper, which always refuses.
    PyObject* init = PyDict_GetItemString(type->tp_dict, "__init__");
    const bool constructible = init != nullptr && !Py_IS_TYPE(init, &PyWrapperDescr_Type);
    for (const auto member : py::reinterpret_borrow<py::dict>(type->tp_dict))
      for (const py::object& function : functions_behind(member.second))
        route_through_own_errors(function);
    if (!constructible) refuse_construction(value);
    // Python's own messages name a type by tp_name, which pybind11 made "intermix._intermix.Scene"
    // ("cannot pickle 'intermix._intermix.Scene' object"); setting __name__ makes it "Scene".
    py::setattr(value, "__name__", py::str(value.attr("__name__")));
  }
}

}  // namespace imx::python
