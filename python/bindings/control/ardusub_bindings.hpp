// The ArduSub controller's bindings: the generic ones (its configuration by
// ArduSub's parameter names), what it drives (PWMs, motor outputs, the
// mixer's inputs), and its parameter table as neurov._core.ARDUSUB_PARAMETERS
// for the Python readers, their range warnings and the docs.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <tuple>

#include "generic_controller.hpp"
#include "neurov/control/ardusub_controller.hpp"

namespace neurov::bindings {

inline void bind_controller(py::module_& m, TypeTag<ArduSubController<double>>) {
  using C = ArduSubController<double>;
  py::class_<C> k = bind_generic_controller<C>(m);
  k.def_property_readonly(
      "pwm", [](const C& c) { return Eigen::VectorXd(c.pwm().head(c.motors())); },
      "PWM [us] of each motor at the last iteration, shape (motors,).");
  k.def_property_readonly(
      "motor_outputs", [](const C& c) { return Eigen::VectorXd(c.motor_outputs().head(c.motors())); },
      "Motor outputs -1..1 before MOT_n_DIRECTION at the last iteration, shape (motors,).");
  k.def_property_readonly(
      "axis_inputs", [](const C& c) { return Vector6<double>(c.axis_inputs()); },
      "The mixer's inputs at the last iteration: roll, pitch, yaw, throttle, forward, lateral "
      "(each -1..1), shape (6,).");
  k.def(
      "mix",
      [](const C& c, const Vector6<double>& inputs) {
        return Eigen::VectorXd(c.mix_pwm(inputs).head(c.motors()));
      },
      py::arg("inputs"),
      "The motor stage alone, as ArduSub's manual mode drives it: the PWM [us] of each motor, shape "
      "(motors,), for the mixer's inputs roll, pitch, yaw, throttle, forward, lateral (each held "
      "within -1..1) through the frame's factors, MOT_n_DIRECTION and MOT_PWM_MIN/MAX. Changes "
      "nothing.");
  py::list table;
  std::apply(
      [&table](const auto&... p) {
        (table.append(py::make_tuple(p.name, p.default_value, p.min, p.max, p.unit, p.doc)), ...);
      },
      ardusub_parameters<double>());
  m.attr("ARDUSUB_PARAMETERS") = table;
}

}  // namespace neurov::bindings
