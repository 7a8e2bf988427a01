// Every controller's configuration struct, bound field by field: the one
// schema Python and C++ share. Defaults are the structs' own; the validator
// is the C++ one (validate() and every controller's constructor run it).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.hpp"
#include "config_class.hpp"
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
constexpr const char* kKdDoc = "K_d, diagonal (6,), >= 0.";
constexpr const char* kDtDoc = "Control period [s], > 0.";

/// A (24,) field that also takes one number for every entry.
template <typename Config>
void parameter_vector(ConfigClass<Config>& cls, const char* name,
                      ParameterVector<double> Config::*member, bool number_fills,
                      const char* doc) {
  cls.field(
      name, [member](const Config& c) { return py::cast(ParameterVector<double>(c.*member)); },
      [member, name, number_fills](Config& c, py::handle v) {
        if (number_fills && (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v)))
          (c.*member).setConstant(py_args::scalar(v, name));
        else
          c.*member = py_args::vector<kRegressorParameters>(v, name);
      },
      doc);
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

void bind_controller_configs(py::module_& m) {
  py::enum_<RobustModification>(m, "RobustModification",
                                "Robust modification of the NN controller's adaptive law.")
      .value("none", RobustModification::none, "The paper's pure gradient law.")
      .value("sigma", RobustModification::sigma, "Leakage: W_dot += -sigma_m W Gamma_w.")
      .value("e_modification", RobustModification::e_modification,
             "Leakage in proportion to the error: W_dot += -kappa ||J^-1 s|| W Gamma_w.")
      .value("projection", RobustModification::projection,
             "After each update, W scaled back onto ||W||_F <= w_max.");

  ConfigClass<PDConfig<double>> pd(m, "PDConfig", "Configuration of PDController.");
  pd.vector<6>("kp", &PDConfig<double>::kp, "K_p, diagonal (6,), >= 0.")
      .vector<6>("kd", &PDConfig<double>::kd, kKdDoc)
      .finish("PD controller");

  using PID = PIDConfig<double>;
  ConfigClass<PID> pid(m, "PIDConfig", "Configuration of PIDController.");
  pid.vector<6>("kp", &PID::kp, "K_p, diagonal (6,), >= 0.")
      .vector<6>("ki", &PID::ki, "K_i, diagonal (6,), >= 0.")
      .vector<6>("kd", &PID::kd, kKdDoc)
      .vector<6>("integral_limit", &PID::integral_limit,
                 "Largest |K_i z| per DOF (6,), > 0 [N, N m].")
      .scalar("dt", &PID::dt, kDtDoc)
      .finish("PID controller");

  using SMC = SlidingModeConfig<double>;
  ConfigClass<SMC> smc(m, "SlidingModeConfig", "Configuration of SlidingModeController.");
  smc.vector<6>("lambda_", &SMC::lambda, kLambdaDoc)
      .vector<6>("kd", &SMC::kd, kKdDoc)
      .vector<6>("k", &SMC::k, "Switching gain K (6,), >= 0 [N, N m].")
      .vector<6>("phi", &SMC::phi, "Boundary-layer width (6,), > 0, in units of s.");
  parameter_vector(smc, "theta", &SMC::theta, false,
                   "The nominal model's theta (24,), e.g. regressor_parameters(vehicle).");
  smc.finish("sliding-mode controller");

  using Lin = LinearAdaptiveConfig<double>;
  ConfigClass<Lin> lin(m, "LinearAdaptiveConfig", "Configuration of LinearAdaptiveController.");
  lin.vector<6>("lambda_", &Lin::lambda, kLambdaDoc).vector<6>("kd", &Lin::kd, kKdDoc);
  parameter_vector(lin, "gamma", &Lin::gamma, true,
                   "Diagonal of Gamma (24,), >= 0 (0 freezes that parameter); a number sets "
                   "every entry.");
  lin.scalar("dt", &Lin::dt, kDtDoc);
  parameter_vector(lin, "theta0", &Lin::theta0, false,
                   "theta_hat(0) (24,): zero, or a nominal guess such as "
                   "regressor_parameters(vehicle).");
  lin.finish("linear adaptive controller");

  using NN = NNAdaptiveConfig<double>;
  ConfigClass<NN> nn(m, "NNAdaptiveConfig", "Configuration of NNAdaptiveController.");
  nn.vector<6>("lambda_", &NN::lambda, kLambdaDoc)
      .vector<6>("kd", &NN::kd, "K_d, diagonal (6,), >= 0 (0 leaves the network alone).")
      .scalar("gamma", &NN::gamma, "Gamma_w = gamma I, >= 0 (the paper: 0.3).")
      .scalar("dt", &NN::dt, "Control period [s], > 0 (the paper: 0.2).")
      .field(
          "modification", [](const NN& c) { return py::cast(c.modification); },
          [](NN& c, py::handle v) { c.modification = parse_modification(v); },
          "The robust modification: a RobustModification or its name.")
      .scalar("sigma_m", &NN::sigma_m, "Leakage of the sigma-modification (> 0 when used).")
      .scalar("kappa", &NN::kappa, "Gain of the e-modification (> 0 when used).")
      .scalar("w_max", &NN::w_max, "Frobenius bound of the projection (> 0 when used).")
      .scalar("dead_zone", &NN::dead_zone,
              "No adaptation while ||s|| < dead_zone (0 disables), >= 0.")
      .finish("NN controller");

  using CT = ComputedTorqueConfig<double>;
  ConfigClass<CT> ct(m, "ComputedTorqueConfig", "Configuration of ComputedTorqueController.");
  ct.vector<6>("lambda_", &CT::lambda, kLambdaDoc)
      .vector<6>("kd", &CT::kd, kKdDoc)
      .field(
          "vehicle",
          [](const CT& c) -> py::object {
            Vehicle<double> v;
            if (Vehicle<double>::create(c.vehicle, v)) return py::none();
            return py::cast(v);
          },
          [](CT& c, py::handle v) {
            if (!py::isinstance<Vehicle<double>>(v))
              throw py::type_error("argument 'vehicle' must be a Vehicle, got " +
                                   std::string(py::str(py::type::handle_of(v))));
            c.vehicle = v.cast<const Vehicle<double>&>().parameters();
          },
          "The nominal model, a Vehicle (None until set).")
      .finish("computed-torque controller");
}

}  // namespace neurov::bindings
