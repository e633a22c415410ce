// intermix's exceptions as Python's: imx::FileError -> OSError (FileNotFoundError,
// IsADirectoryError, PermissionError by its errno), any other imx::Error -> ValueError (a scene,
// value or file content at fault), imx::OutOfMemory and std::bad_alloc -> MemoryError,
// RenderFailure -> RuntimeError, imx::Cancelled -> KeyboardInterrupt. The message is the
// library's one line.
#include <cerrno>
#include <new>

#include <fmt/format.h>

#include "bindings.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"

namespace imx::python {
namespace {

PyObject* os_error_type(int code) {
  switch (code) {
    case ENOENT:
      return PyExc_FileNotFoundError;
    case EISDIR:
      return PyExc_IsADirectoryError;
    case ENOTDIR:
      return PyExc_NotADirectoryError;
    case EACCES:
    case EPERM:
      return PyExc_PermissionError;
    default:
      return PyExc_OSError;
  }
}

// An OSError subclass with the message alone as its text and `errno` set when known.
void set_file_error(const FileError& e) {
  PyObject* type = os_error_type(e.code());
  py::object error = py::reinterpret_steal<py::object>(PyObject_CallFunction(type, "s", e.what()));
  if (!error) return;  // the call set its own exception (out of memory)
  if (e.code() != 0) PyObject_SetAttrString(error.ptr(), "errno", py::int_(e.code()).ptr());
  PyErr_SetObject(type, error.ptr());
}

}  // namespace

void bind_errors(py::module_& m) {
  m.def(
      "set_max_memory",
      [](const py::object& bytes) {
        if (!py::isinstance<py::int_>(bytes) || py::isinstance<py::bool_>(bytes))
          throw py::type_error(
              fmt::format("set_max_memory: bytes must be an int, got {}",
                          py::str(py::type::of(bytes).attr("__name__")).cast<std::string>()));
        const long long value = bytes.cast<long long>();  // OverflowError beyond 2**63
        if (value < 0)
          throw py::value_error(fmt::format("set_max_memory: bytes is {}, not 0 or more", value));
        InputLimits limits = input_limits();
        limits.max_memory = static_cast<uint64_t>(value);
        set_input_limits(limits);
      },
      py::arg("bytes"),
      "Sets the memory one input or frame may ask for, in bytes (0: the default, half of physical "
      "memory), as the CLI's --max-memory. More raises MemoryError naming the input and the "
      "budget.");
  m.def(
      "max_memory", [] { return input_limits().max_memory; },
      "The memory budget in force, in bytes (see set_max_memory).");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Cancelled& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const FileError& e) {
      set_file_error(e);
    } catch (const OutOfMemory& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    } catch (const std::bad_alloc&) {
      PyErr_SetString(PyExc_MemoryError, out_of_memory_message("intermix").c_str());
    } catch (const Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const RenderFailure& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
}

}  // namespace imx::python
