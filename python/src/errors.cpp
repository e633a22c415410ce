// intermix's exceptions as Python's: imx::FileError -> OSError (FileNotFoundError,
// IsADirectoryError, PermissionError by its errno), any other imx::Error -> ValueError (a scene,
// value or file content at fault), imx::OutOfMemory and std::bad_alloc -> MemoryError,
// RenderFailure -> RuntimeError, imx::Cancelled -> KeyboardInterrupt. The message is the
// library's one line.
#include <cerrno>
#include <cstring>
#include <new>

#include <fmt/format.h>

#include "arguments.hpp"
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
    case EEXIST:  // an output that names an input of this process
      return PyExc_FileExistsError;
    case EACCES:
    case EPERM:
      return PyExc_PermissionError;
    default:
      return PyExc_OSError;
  }
}

// A message as Python text. Bytes that are not UTF-8 (quoted from a binary file, or a file name
// os.fsdecode gave) show as \xNN: a strict decode failed and left the exception without text.
py::object message_text(const char* message) {
  return py::reinterpret_steal<py::object>(PyUnicode_DecodeUTF8(
      message, static_cast<Py_ssize_t>(std::strlen(message)), "backslashreplace"));
}

void set_error(PyObject* type, const char* message) {
  const py::object text = message_text(message);
  if (text) PyErr_SetObject(type, text.ptr());  // else the decode set its own (out of memory)
}

// An OSError subclass with the message alone as its text and `errno` set when known.
void set_file_error(const FileError& e) {
  PyObject* type = os_error_type(e.code());
  const py::object text = message_text(e.what());
  if (!text) return;
  py::object error =
      py::reinterpret_steal<py::object>(PyObject_CallFunctionObjArgs(type, text.ptr(), nullptr));
  if (!error) return;  // the call set its own exception (out of memory)
  if (e.code() != 0) PyObject_SetAttrString(error.ptr(), "errno", py::int_(e.code()).ptr());
  PyErr_SetObject(type, error.ptr());
}

}  // namespace

void bind_errors(py::module_& m) {
  m.def(
      "set_max_memory",
      [](const IntParameter& bytes) {
        InputLimits limits = input_limits();
        limits.max_memory =
            static_cast<uint64_t>(int_at_least(bytes, {"set_max_memory", "bytes"}, 0));
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
      set_error(PyExc_KeyboardInterrupt, e.what());
    } catch (const FileError& e) {
      set_file_error(e);
    } catch (const OutOfMemory& e) {
      set_error(PyExc_MemoryError, e.what());
    } catch (const std::bad_alloc&) {
      set_error(PyExc_MemoryError, out_of_memory_message("intermix").c_str());
    } catch (const Error& e) {
      set_error(PyExc_ValueError, e.what());
    } catch (const RenderFailure& e) {
      set_error(PyExc_RuntimeError, e.what());
    }
  });
}

}  // namespace imx::python
