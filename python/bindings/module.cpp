// neurov._core: the compiled part of neurov. The Python package re-exports it.
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "neurov/core/status.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
  m.doc() =
      "neurov's C++ core: vehicle dynamics, Euler-angle kinematics, integrator, "
      "reference model and controllers (double precision). Import from `neurov`, not from here.";
  m.attr("__version__") = NEUROV_VERSION_INFO;

  py::enum_<neurov::Status>(m, "Status", "Result of a real-time step; `ok` is 0.")
      .value("ok", neurov::Status::ok, "The step succeeded.")
      .value("near_singularity", neurov::Status::near_singularity,
             "Pitch at or near +-90 deg, where the Euler-angle transform is singular.")
      .value("non_finite_input", neurov::Status::non_finite_input,
             "An input held NaN or Inf.")
      .value("invalid_argument", neurov::Status::invalid_argument,
             "An input was outside what the function accepts.")
      .value("non_finite_output", neurov::Status::non_finite_output,
             "The result overflowed; safe values were written instead.");

  neurov::bindings::bind_kinematics(m);
  neurov::bindings::bind_vehicle(m);
  neurov::bindings::bind_controllers(m);
  neurov::bindings::bind_thrusters(m);
  neurov::bindings::bind_sim_config(m);
  neurov::bindings::bind_simulator(m);
  neurov::bindings::bind_closed_loop(m);
  neurov::bindings::bind_bench(m);
}
