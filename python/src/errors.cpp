// The library's exceptions as Python exceptions (docs/python.md, "Errors"): every exception a call
// into the library throws reaches Python as one of these, with the command line's message.

#include <pybind11/stl.h>

#include <filesystem>
#include <sstream>

#include "bindings.hpp"
#include "emrm/core/config.hpp"
#include "emrm/core/interrupt.hpp"

namespace emrm::python {
namespace {

// The exception classes, created once with the module and alive as long as the interpreter.
struct ExceptionTypes {
  py::handle input;
  py::handle usage;
  py::handle error;
  py::handle interrupted;
};
ExceptionTypes g_types;

py::handle new_exception(py::module_& m, const char* name, PyObject* base, const char* doc) {
  const std::string qualified = std::string("emrm.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base, nullptr);
  if (type == nullptr) throw py::error_already_set();
  m.add_object(name, py::handle(type));
  return type;
}

py::object optional_int(int value) { return value > 0 ? py::object(py::int_(value)) : py::object(py::none()); }

// emrm.InputError carrying where the input was wrong.
py::object input_error_object(const InputError& error) {
  py::object exception = g_types.input(py::str(error.what()));
  const SourceLocation& where = error.where();
  exception.attr("file") = where.file.empty() ? py::object(py::none()) : py::object(py::str(where.file));
  exception.attr("line") = optional_int(where.line);
  exception.attr("column") = optional_int(where.column);
  exception.attr("message") = py::str(error.message());
  const auto* config = dynamic_cast<const core::ConfigError*>(&error);
  exception.attr("field") = config != nullptr ? py::object(py::str(config->path().str())) : py::object(py::none());
  return exception;
}

void set_error(py::handle type, const py::object& exception) { PyErr_SetObject(type.ptr(), exception.ptr()); }

// By value: pybind11::ExceptionTranslator's signature.
void translate(std::exception_ptr thrown) {  // NOLINT(performance-unnecessary-value-param)
  try {
    if (thrown) std::rethrow_exception(thrown);
  } catch (const core::Interrupted& e) {
    py::object exception = g_types.interrupted(py::str(e.what()));
    exception.attr("signal") = e.signal();
    set_error(g_types.interrupted, exception);
  } catch (const InputError& e) {
    set_error(g_types.input, input_error_object(e));
  } catch (const UsageError& e) {
    PyErr_SetString(g_types.usage.ptr(), e.what());
  } catch (const Error& e) {
    PyErr_SetString(g_types.error.ptr(), e.what());
  } catch (const std::filesystem::filesystem_error& e) {  // OSError picks its subclass (FileNotFoundError, …)
    set_error(PyExc_OSError, py::reinterpret_borrow<py::object>(PyExc_OSError)(e.code().value(), e.code().message(),
                                                                               e.path1().string()));
  }
}

}  // namespace

void raise_input_error_in(const InputError& error, const std::string& text) {
  py::object exception = input_error_object(error);
  std::istringstream lines(text);
  std::string line;
  for (int n = 1; std::getline(lines, line); ++n)
    if (n == error.where().line && py::hasattr(exception, "add_note"))
      exception.attr("add_note")("in the mapping as the loader read it (JSON), line " + std::to_string(n) + ": " +
                                 line);
  set_error(g_types.input, exception);
  throw py::error_already_set();
}

void bind_errors(py::module_& m) {
  g_types.input = new_exception(
      m, "InputError", PyExc_ValueError,
      "Bad input: a malformed file, a wrong type, a value out of range. str() is the command line's message\n"
      "(FILE:LINE:COLUMN: error: MESSAGE); .file, .line and .column say where (None when unknown),\n"
      ".message what, and .field the path of the field in a configuration built in code.");
  g_types.usage = new_exception(
      m, "UsageError", PyExc_ValueError,
      "A bad argument: an unknown strategy, a cell out of range, a results folder of another configuration.");
  g_types.error = new_exception(m, "Error", PyExc_RuntimeError,
                                "Any other error of the library, such as a results store that cannot be written.");
  g_types.interrupted = new_exception(
      m, "Interrupted", PyExc_KeyboardInterrupt,
      "Ctrl-C stopped a sweep after it stored the cells in flight; calling it again resumes it. .signal is\n"
      "the signal's number.");
  py::register_exception_translator(translate);
}

}  // namespace emrm::python
