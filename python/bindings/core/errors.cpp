#include "core/errors.hpp"

#include <cmath>
#include <string>

#include "bindings.hpp"

namespace neurov::bindings {

namespace py = pybind11;

namespace {

// Made once, when the module is imported, and kept for the process's life:
// a module is never unloaded, and an exception class must outlive every
// instance a caller may still hold.
PyObject* validation_error_type = nullptr;

}  // namespace

void raise_validation_error(const ValidationError& e, const char* what) {
  if (!e) return;
  char buf[320];
  e.format(buf, sizeof buf);
  py::object cls = py::reinterpret_borrow<py::object>(validation_error_type);
  py::object exc = cls(std::string(what) + ": " + buf);
  exc.attr("field") = py::str(e.field);
  exc.attr("index") = e.index;
  exc.attr("value") = std::isnan(e.value) ? py::object(py::none()) : py::object(py::float_(e.value));
  exc.attr("expected") = py::str(e.expected ? e.expected : "");
  PyErr_SetObject(validation_error_type, exc.ptr());
  throw py::error_already_set();
}

void bind_errors(py::module_& m) {
  const auto make = [&m](const char* name, PyObject* base, const char* doc,
                         PyObject* attributes = nullptr) {
    const std::string qualified = std::string("neurov._core.") + name;
    PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base, attributes);
    if (cls == nullptr) throw py::error_already_set();
    m.add_object(name, py::reinterpret_borrow<py::object>(cls));
    return cls;
  };
  PyObject* base = make("NeurovError", PyExc_ValueError,
                        "The base of every error neurov raises for bad input (a ValueError).");
  // The attributes raise_validation_error sets, declared for type checkers
  // (tools/generate_stubs.py writes them into the stub).
  py::dict attributes;
  attributes["__annotations__"] = py::dict(py::arg("field") = "str", py::arg("index") = "int",
                                           py::arg("value") = "float | None",
                                           py::arg("expected") = "str");
  validation_error_type = make(
      "ValidationError", base,
      "A configuration refused by its C++ validator. Attributes: field (the offending "
      "field's C++ name), index (the element, row-major for a matrix, or -1 for the whole "
      "field), value (the offending value, None for a whole matrix) and expected (what the "
      "field must satisfy).",
      attributes.ptr());
}

}  // namespace neurov::bindings
