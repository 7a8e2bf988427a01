// Every controller's configuration struct, bound field by field: the one
// schema Python and C++ share. Defaults are the structs' own; the validator
// is the C++ one (validate() and every controller's constructor run it).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.hpp"
#include "fields.hpp"
#include "generic_controller.hpp"
#include "neurov/control/built_in_controllers.hpp"
#include "neurov/control/computed_torque_controller.hpp"
#include "neurov/control/linear_adaptive_controller.hpp"
#include "neurov/control/nn_controller.hpp"
#include "neurov/control/pd_controller.hpp"
#include "neurov/control/pid_controller.hpp"
#include "neurov/control/sliding_mode_controller.hpp"
#include "neurov/model/regressor.hpp"
#include "neurov/model/vehicle.hpp"
#include "numpy_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;

namespace {

constexpr const char* kLambdaDoc = "Lambda in s = eta_tilde_dot + Lambda eta_tilde, diagonal (6,), > 0.";
constexpr const char* kKpDoc = "K_p, diagonal (6,), >= 0.";
constexpr const char* kKdDoc = "K_d, diagonal (6,), >= 0.";
constexpr const char* kDtDoc = "Control period [s], > 0.";

/// The Python class of a controller's configuration, its fields to follow.
template <typename Config>
Fields<Config> config_fields(py::module_& m, const char* name, const char* controller) {
  return Fields<Config>(m, name, (std::string("Configuration of ") + controller + ".").c_str());
}

/// The fields of a controller on the sliding variable s: Lambda and K_d first.
template <typename T>
Fields<T> sliding_fields(py::module_& m, const char* name, const char* controller,
                         const char* kd_doc = kKdDoc) {
  Fields<T> f = config_fields<T>(m, name, controller);
  // Members of SlidingGains, T's base: named as T's for the field binder.
  using Gain = Vector6<double> T::*;
  f.vector("lambda_", Gain{&T::lambda}, kLambdaDoc).vector("kd", Gain{&T::kd}, kd_doc);
  return f;
}

}  // namespace

RobustModification parse_modification(py::handle obj) {
  if (py::isinstance<RobustModification>(obj)) return obj.cast<RobustModification>();
  const auto s =
      py_args::choice(obj, "modification", {"none", "sigma", "e_modification", "projection"});
  for (auto m : {RobustModification::sigma, RobustModification::e_modification,
                 RobustModification::projection})
    if (s == to_string(m)) return m;
  return RobustModification::none;
}

// The configurations with bindings of their own; any other built-in
// controller's comes from its config_fields (generic_controller.hpp).
void bind_config(py::module_& m, TypeTag<PDController<double>>) {
  using PD = PDConfig<double>;
  config_fields<PD>(m, "PDConfig", "PDController")
      .vector("kp", &PD::kp, kKpDoc)
      .vector("kd", &PD::kd, kKdDoc)
      .validator("PD controller")
      .finish();
}

void bind_config(py::module_& m, TypeTag<PIDController<double>>) {
  using PID = PIDConfig<double>;
  config_fields<PID>(m, "PIDConfig", "PIDController")
      .vector("kp", &PID::kp, kKpDoc)
      .vector("ki", &PID::ki, "K_i, diagonal (6,), >= 0.")
      .vector("kd", &PID::kd, kKdDoc)
      .vector("integral_limit", &PID::integral_limit, "Largest |K_i z| per DOF (6,), > 0 [N, N m].")
      .value("dt", &PID::dt, kDtDoc)
      .validator("PID controller")
      .finish();
}

void bind_config(py::module_& m, TypeTag<SlidingModeController<double>>) {
  using SMC = SlidingModeConfig<double>;
  sliding_fields<SMC>(m, "SlidingModeConfig", "SlidingModeController")
      .vector("k", &SMC::k, "Switching gain K (6,), >= 0 [N, N m].")
      .vector("phi", &SMC::phi, "Boundary-layer width (6,), > 0, in units of s.")
      .vector("theta", &SMC::theta,
              "The nominal model's theta (24,), e.g. regressor_parameters(vehicle).")
      .validator("sliding-mode controller")
      .finish();
}

void bind_config(py::module_& m, TypeTag<LinearAdaptiveController<double>>) {
  using Lin = LinearAdaptiveConfig<double>;
  sliding_fields<Lin>(m, "LinearAdaptiveConfig", "LinearAdaptiveController")
      .vector_or_number("gamma", &Lin::gamma,
                        "Diagonal of Gamma (24,), >= 0 (0 freezes that parameter); a number "
                        "sets every entry.")
      .value("dt", &Lin::dt, kDtDoc)
      .vector("theta0", &Lin::theta0,
              "theta_hat(0) (24,): zero, or a nominal guess such as "
              "regressor_parameters(vehicle).")
      .validator("linear adaptive controller")
      .finish();
}

void bind_config(py::module_& m, TypeTag<NNAdaptiveController<double>>) {
  using NN = NNAdaptiveConfig<double>;
  sliding_fields<NN>(m, "NNAdaptiveConfig", "NNAdaptiveController",
                     "K_d, diagonal (6,), >= 0 (0 leaves the network alone).")
      .value("gamma", &NN::gamma, "Gamma_w = gamma I, >= 0 (the paper: 0.3).")
      .value("dt", &NN::dt, "Control period [s], > 0 (the paper: 0.2).")
      .field(
          "modification", [](const NN& c) { return c.modification; },
          [](NN& c, const typed::EnumOrStr<RobustModification>& v, const std::string&) {
            c.modification = parse_modification(v);
          },
          "The robust modification: a RobustModification or its name.")
      .value("sigma_m", &NN::sigma_m, "Leakage of the sigma-modification (> 0 when used).")
      .value("kappa", &NN::kappa, "Gain of the e-modification (> 0 when used).")
      .value("w_max", &NN::w_max, "Frobenius bound of the projection (> 0 when used).")
      .value("dead_zone", &NN::dead_zone,
             "No adaptation while ||s|| < dead_zone (0 disables), >= 0.")
      .validator("NN controller")
      .finish();
}

void bind_config(py::module_& m, TypeTag<ComputedTorqueController<double>>) {
  using CT = ComputedTorqueConfig<double>;
  sliding_fields<CT>(m, "ComputedTorqueConfig", "ComputedTorqueController")
      .field(
          "vehicle",
          [](const CT& c) -> py::typing::Optional<Vehicle<double>> {
            Vehicle<double> v;
            if (Vehicle<double>::create(c.vehicle, v)) return py::none();
            return py::cast(v);
          },
          [](CT& c, const typed::Of<Vehicle<double>>& v, const std::string& name) {
            if (!py::isinstance<Vehicle<double>>(v))
              throw py::type_error(name + " must be a Vehicle, got " +
                                   std::string(py::str(py::type::handle_of(v))));
            c.vehicle = v.cast<const Vehicle<double>&>().parameters();
          },
          "The nominal model, a Vehicle (None until set).")
      .validator("computed-torque controller")
      .finish();
}

template <typename Controller>
void bind_config(py::module_& m, TypeTag<Controller>) {
  bind_generic_config<Controller>(m);
}

void bind_controller_configs(py::module_& m) {
  py::enum_<RobustModification>(m, "RobustModification",
                                "Robust modification of the NN controller's adaptive law.")
      .value("none", RobustModification::none, "The paper's pure gradient law.")
      .value("sigma", RobustModification::sigma, "Leakage: W_dot += -sigma_m W Gamma_w.")
      .value("e_modification", RobustModification::e_modification,
             "Leakage in proportion to the error: W_dot += -kappa ||J^-1 s|| W Gamma_w.")
      .value("projection", RobustModification::projection,
             "After each update, W scaled back onto ||W||_F <= w_max.");

  for_each_type(BuiltInControllers<double>{}, [&m](auto tag) { bind_config(m, tag); });
}

}  // namespace neurov::bindings
