// intermix's exceptions as Python's: imx::FileError -> OSError (FileNotFoundError,
// IsADirectoryError, PermissionError by its errno), any other imx::Error -> ValueError (a scene,
// value or file content at fault), RenderFailure -> RuntimeError, imx::Cancelled ->
// KeyboardInterrupt. The message is the library's one line.
#include <cerrno>

#include "bindings.hpp"
#include "intermix/error.hpp"

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

void bind_errors(py::module_&) {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Cancelled& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const FileError& e) {
      set_file_error(e);
    } catch (const Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const RenderFailure& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
}

}  // namespace imx::python
