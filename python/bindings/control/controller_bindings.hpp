// What the bindings of every controller share: the refused step as a Python
// error, the tracking error as a dict, the checked step, and the members
// every controller class has (step, reset, s, tracking, config, and the
// constructor from its bound configuration), and the keyword constructor
// that fills the configuration from its arguments.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>
#include <type_traits>
#include <utility>

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

inline typed::ArraysDict tracking_dict(const TrackingError<double>& e) {
  using Vec6 = Vector6<double>;
  py::dict d;
  d["eta_tilde"] = Vec6(e.eta_tilde);
  d["eta_tilde_dot"] = Vec6(e.eta_tilde_dot);
  d["s"] = Vec6(e.s);
  d["eta_r_dot"] = Vec6(e.eta_r_dot);
  d["eta_r_ddot"] = Vec6(e.eta_r_ddot);
  d["nu_r"] = Vec6(e.nu_r);
  d["nu_r_dot"] = Vec6(e.nu_r_dot);
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

/// A configuration member from a Python argument named `name` in its
/// errors: a real number, or a vector of the member's length.
template <typename D>
D converted(py::handle v, const char* name) {
  if constexpr (std::is_same_v<D, double>)
    return py_args::scalar(v, name);
  else
    return py_args::vector<D::RowsAtCompileTime>(v, name);
}

/// An argument of a controller's keyword constructor: it sets `member` of
/// the configuration, converted by `convert`.
template <typename Config, typename D>
struct ConfigArg {
  const char* name;
  D Config::*member;
  D (*convert)(py::handle, const char*);

  void apply(Config& config, py::handle v) const { config.*member = convert(v, name); }
  py::arg declared() const { return py::arg(name); }
};

/// The same with a default value, shown in the signature.
template <typename Config, typename D>
struct DefaultedConfigArg : ConfigArg<Config, D> {
  py::object default_value;

  py::arg_v declared() const { return py::arg(this->name) = default_value; }
};

template <typename Config, typename D>
ConfigArg<Config, D> config_arg(const char* name, D Config::*member,
                                D (*convert)(py::handle, const char*) = &converted<D>) {
  return {name, member, convert};
}

template <typename Config, typename D>
DefaultedConfigArg<Config, D> config_arg_or(const char* name, D Config::*member,
                                            py::object default_value,
                                            D (*convert)(py::handle, const char*) = &converted<D>) {
  return {{name, member, convert}, std::move(default_value)};
}

// Every argument of a keyword constructor arrives as a handle: one per
// ConfigArg, so that the constructor's parameters can be a pack.
// Declared as what the member is: a number, an enum (or its name) or an array.
template <typename>
struct python_argument;
template <typename D, typename = void>
struct member_argument {
  using type = typed::ArrayLike;
};
template <typename D>
struct member_argument<D, std::enable_if_t<std::is_floating_point_v<D>>> {
  using type = typed::Real;
};
template <typename D>
struct member_argument<D, std::enable_if_t<std::is_enum_v<D>>> {
  using type = typed::EnumOrStr<D>;
};
template <typename Config, typename D>
struct python_argument<ConfigArg<Config, D>> : member_argument<D> {};
template <typename Config, typename D>
struct python_argument<DefaultedConfigArg<Config, D>> : member_argument<D> {};

/// The constructor from a configuration object, then the keyword
/// constructor whose arguments, in order, are `args` (each setting one member
/// of the configuration). The C++ validator's message is a ValueError
/// prefixed with `what`.
template <typename Controller, typename... Args>
void def_constructors(py::class_<Controller>& cls, const char* what, const char* doc,
                      Args... args) {
  def_init_from_config<Controller>(cls, what);
  cls.def(py::init([what, args...](typename python_argument<Args>::type... values) {
            typename Controller::Config config;
            (args.apply(config, values), ...);
            return from_config<Controller>(config, what);
          }),
          args.declared()..., doc);
}

}  // namespace neurov::bindings
