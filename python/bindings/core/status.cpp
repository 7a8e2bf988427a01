#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "neurov/core/status.hpp"

namespace neurov::bindings {

namespace py = pybind11;

void bind_status(py::module_& m) {
  py::enum_<Status>(m, "Status", "Result of a real-time step; `ok` is 0.")
      .value("ok", Status::ok, "The step succeeded.")
      .value("near_singularity", Status::near_singularity,
             "Pitch at or near +-90 deg, where the Euler-angle transform is singular.")
      .value("non_finite_input", Status::non_finite_input, "An input held NaN or Inf.")
      .value("invalid_argument", Status::invalid_argument,
             "An input was outside what the function accepts.")
      .value("non_finite_output", Status::non_finite_output,
             "The result overflowed; safe values were written instead.");
}

}  // namespace neurov::bindings
