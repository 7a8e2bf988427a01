// What the bindings of every controller share: the refused step as a Python
// error, the tracking error as a dict, the checked step, and the members
// every controller class has (step, reset, s, tracking, config, and the
// constructor from its bound configuration).
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>

#include "neurov/control/nn_controller.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "numpy_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;

/// A RobustModification, or its name; TypeError or ValueError naming
/// 'modification' otherwise (controller_configs.cpp).
RobustModification parse_modification(py::handle obj);

/// Raises ValueError for a refused step (the controller is unchanged).
inline void raise_step_status(Status s) {
  switch (s) {
    case Status::ok:
      return;
    case Status::near_singularity:
      throw py::value_error(
          "step refused: argument 'eta' has its pitch at the Euler-angle singularity "
          "(cos(theta) = 0); the controller's state is unchanged");
    case Status::non_finite_output:
      throw py::value_error(
          "step refused: the inputs are so large that tau or the adaptation overflowed; the "
          "controller's state is unchanged");
    default:
      throw py::value_error(std::string("step refused (") + to_string(s) +
                            "); the controller's state is unchanged");
  }
}

/// The tracking error's (6,) fields by name: what its dict and its snapshot hold.
struct TrackingField {
  const char* name;
  Vector6<double> TrackingError<double>::*member;
};
using TE = TrackingError<double>;
inline constexpr TrackingField kTrackingFields[] = {
    {"eta_tilde", &TE::eta_tilde}, {"eta_tilde_dot", &TE::eta_tilde_dot}, {"s", &TE::s},
    {"eta_r_dot", &TE::eta_r_dot}, {"eta_r_ddot", &TE::eta_r_ddot},       {"nu_r", &TE::nu_r},
    {"nu_r_dot", &TE::nu_r_dot}};

inline typed::ArraysDict tracking_dict(const TrackingError<double>& e) {
  py::dict d;
  for (const TrackingField& f : kTrackingFields) d[f.name] = Vector6<double>(e.*(f.member));
  return d;
}

/// The step every controller shares: checked arguments in, tau out, a
/// refused step raises and changes nothing.
template <typename Controller>
Vector6<double> checked_step(Controller& c, const typed::ArrayLike& eta, const typed::ArrayLike& nu, const typed::ArrayLike& eta_d,
                             const typed::ArrayLike& eta_d_dot, const typed::ArrayLike& eta_d_ddot) {
  const Vector6<double> e = py_args::vector<6>(eta, "eta");
  const Vector6<double> n = py_args::vector<6>(nu, "nu");
  const Vector6<double> ed = py_args::vector<6>(eta_d, "eta_d");
  const Vector6<double> edd = py_args::vector<6>(eta_d_dot, "eta_d_dot");
  const Vector6<double> eddd = py_args::vector<6>(eta_d_ddot, "eta_d_ddot");
  Vector6<double> tau;
  raise_step_status(c.step(e, n, ed, edd, eddd, tau));
  return tau;
}

/// A controller built by its create(config, out): the C++ validator's
/// message as ValueError, prefixed with `what`.
template <typename Controller>
Controller from_config(const typename Controller::Config& config, const char* what) {
  Controller c;
  py_args::raise_if_invalid(Controller::create(config, c), what);
  return c;
}

constexpr const char* kStepDoc =
    "One control step from the measured pose eta (6,) and body velocity nu (6,) and the "
    "desired eta_d, eta_d_dot, eta_d_ddot (6,) in the earth frame; returns tau (6,), the body "
    "forces and moments. A NaN/Inf input, or the pitch singularity, raises ValueError and "
    "leaves the controller exactly as it was.";

/// step, reset, s, tracking and config: the members of every controller.
template <typename Controller, typename Class>
void def_common(Class& cls) {
  cls.def("step", &checked_step<Controller>, py::arg("eta"), py::arg("nu"), py::arg("eta_d"),
          py::arg("eta_d_dot"), py::arg("eta_d_ddot"), kStepDoc)
      .def("reset", &Controller::reset, "Back to the initial state and a zero history.")
      .def_property_readonly(
          "s", [](const Controller& c) { return Vector6<double>(c.tracking().s); },
          "Filtered tracking error s of the last step, shape (6,).")
      .def_property_readonly(
          "tracking", [](const Controller& c) { return tracking_dict(c.tracking()); },
          "Tracking error and virtual reference of the last step: a dict of (6,) arrays "
          "eta_tilde, eta_tilde_dot, s, eta_r_dot, eta_r_ddot, nu_r, nu_r_dot.")
      .def_property_readonly(
          "config", [](const Controller& c) { return c.config(); },
          "A copy of the configuration the controller was built from.");
}

/// The constructor from a bound configuration object; registered before the
/// keyword constructors so that pybind11 tries it first.
template <typename Controller, typename Class>
void def_init_from_config(Class& cls, const char* what) {
  cls.def(py::init([what](const typename Controller::Config& config) {
            return from_config<Controller>(config, what);
          }),
          py::arg("config"),
          "Builds the controller from its configuration object; ValueError names a bad field.");
}

}  // namespace neurov::bindings
