// The controllers: each constructed from its bound configuration object or
// from keyword arguments (the signatures the tests and scripts use), with
// the members every controller shares (controller_bindings.hpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "bindings.hpp"
#include "controller_bindings.hpp"
#include "ardusub_bindings.hpp"
#include "generic_controller.hpp"
#include "neurov/control/built_in_controllers.hpp"
#include "neurov/control/computed_torque_controller.hpp"
#include "neurov/control/linear_adaptive_controller.hpp"
#include "neurov/control/nn_controller.hpp"
#include "neurov/control/pd_controller.hpp"
#include "neurov/control/pid_controller.hpp"
#include "neurov/control/rbf_network.hpp"
#include "neurov/control/sliding_mode_controller.hpp"
#include "neurov/model/regressor.hpp"
#include "neurov/model/vehicle.hpp"
#include "numpy_args.hpp"
#include "snapshot.hpp"

namespace neurov::bindings {

namespace py = pybind11;
using Vec6 = Vector6<double>;
using Network = RbfNetwork<double>;  // dynamic inputs and centres
using NNController = NNAdaptiveController<double>;
using LinController = LinearAdaptiveController<double>;
using PD = PDController<double>;
using PID = PIDController<double>;
using SMC = SlidingModeController<double>;
using CT = ComputedTorqueController<double>;
using LinConfig = LinearAdaptiveConfig<double>;
using PIDConfigD = PIDConfig<double>;
using SMCConfig = SlidingModeConfig<double>;

namespace {

/// The NN controller from a network with any number of inputs (checked to
/// be 24) and its configuration.
NNController make_nn(const Network& network, const NNAdaptiveConfig<double>& cfg,
                     const typed::OptionalArrayLike& learning_rates) {
  if (network.inputs() != kNNInputs)
    throw py::value_error("argument 'network' must have 24 inputs ([nu_r_dot; nu_r; nu; eta]), "
                          "got " + std::to_string(network.inputs()));
  NNController::Network fixed_inputs;
  py_args::raise_if_invalid(
      NNController::Network::create(network.centres(), network.widths(), network.input_offset(),
                                    network.input_scale(), fixed_inputs),
      "network");
  fixed_inputs.set_weights(network.weights());
  NNController c;
  py_args::raise_if_invalid(NNController::create(fixed_inputs, cfg, c), "NN controller");
  if (!learning_rates.is_none()) {
    const Eigen::VectorXd rates =
        py_args::dynamic_vector(learning_rates, "learning_rates", network.centres_count());
    if ((rates.array() < 0.0).any())
      throw py::value_error("argument 'learning_rates' must be >= 0");
    c.set_learning_rates(rates);
  }
  return c;
}

/// The NN controller's snapshot: its network (centres, widths, input
/// normalisation, W(0)), per-centre rates and everything it learnt.
py::dict nn_state(const NNController& c) {
  py::dict d = controller_state(c);
  const NNController::Network& n = c.network();
  d["centres"] = Eigen::MatrixXd(n.centres());
  d["widths"] = Eigen::VectorXd(n.widths());
  d["input_offset"] = Eigen::VectorXd(n.input_offset());
  d["input_scale"] = Eigen::VectorXd(n.input_scale());
  d["initial_weights"] = Eigen::MatrixXd(c.initial_weights());
  d["learning_rates"] = Eigen::VectorXd(c.learning_rates());
  d["weights"] = Eigen::MatrixXd(c.weights());
  d["weight_norm"] = c.weight_norm();
  d["basis"] = Eigen::VectorXd(c.basis());
  d["network_output"] = Vec6(c.network_output());
  d["adapted"] = c.adapted();
  return d;
}

NNController nn_from_state(const py::dict& d) {
  const Eigen::MatrixXd centres = py_args::dynamic_matrix(snapshot_field(d, "centres"), "centres", -1, kNNInputs);
  const Eigen::Index n = centres.rows();
  NNController::Network network;
  py_args::raise_if_invalid(
      NNController::Network::create(
          centres, py_args::dynamic_vector(snapshot_field(d, "widths"), "widths", n),
          py_args::dynamic_vector(snapshot_field(d, "input_offset"), "input_offset", kNNInputs),
          py_args::dynamic_vector(snapshot_field(d, "input_scale"), "input_scale", kNNInputs),
          network),
      "network");
  if (!network.set_weights(py_args::dynamic_matrix(snapshot_field(d, "initial_weights"),
                                                   "initial_weights", 6, n)))
    throw py::value_error("snapshot: 'initial_weights' must be finite");
  NNController c;
  py_args::raise_if_invalid(
      NNController::create(network, snapshot_field(d, "config").cast<NNAdaptiveConfig<double>>(), c),
      "NN controller");
  raise_unless_restored(
      c.set_learning_rates(
          py_args::dynamic_vector(snapshot_field(d, "learning_rates"), "learning_rates", n)) &&
          c.restore(tracking_from_dict(d), status_from_dict(d),
                    py_args::dynamic_matrix(snapshot_field(d, "weights"), "weights", 6, n),
                    py_args::scalar(snapshot_field(d, "weight_norm"), "weight_norm"),
                    py_args::dynamic_vector(snapshot_field(d, "basis"), "basis", n),
                    py_args::vector<6>(snapshot_field(d, "network_output"), "network_output"),
                    snapshot_field(d, "adapted").cast<bool>()),
      "NN controller");
  return c;
}

/// Gamma of the linear adaptive controller: (24,), or one number for every entry.
ParameterVector<double> gamma_from(py::handle gamma, const char* name) {
  if (py::isinstance<py::float_>(gamma) || py::isinstance<py::int_>(gamma))
    return ParameterVector<double>::Constant(py_args::scalar(gamma, name));
  return py_args::vector<kRegressorParameters>(gamma, name);
}

/// theta_hat(0) of the linear adaptive controller: (24,), None for zero.
ParameterVector<double> theta0_from(py::handle theta0, const char* name) {
  return theta0.is_none() ? ParameterVector<double>::Zero()
                          : py_args::vector<kRegressorParameters>(theta0, name);
}

}  // namespace

// The controllers with bindings of their own; any other built-in
// controller's come from generic_controller.hpp.
void bind_controller(py::module_& m, TypeTag<NNController>) {
  // --- NN adaptive controller -------------------------------------------------
  py::class_<NNController> nn(
      m, "NNAdaptiveController",
      "Direct adaptive RBF-network controller (eq. 35, 37): tau = W g(x) - J^T K_d s with "
      "x = [nu_r_dot; nu_r; nu; eta] (24 inputs), then W <- W - dt (J^-1 s) g(x)^T Gamma_w. "
      "tau uses the weights from before the update.");
  nn.def(py::init(&make_nn), py::arg("network"), py::arg("config"), py::kw_only(),
         py::arg("learning_rates") = py::none(),
         "network: an RbfNetwork with 24 inputs (copied; its weights are W(0)); config: an "
         "NNAdaptiveConfig; learning_rates (N,): per-centre Gamma_w.");
  nn.def(py::init([](const Network& network, const typed::ArrayLike& lambda_, const typed::ArrayLike& kd, const typed::Real& gamma,
                     const typed::Real& dt, const typed::EnumOrStr<RobustModification>& modification, const typed::Real& sigma_m, const typed::Real& kappa,
                     const typed::Real& w_max, const typed::Real& dead_zone, const typed::OptionalArrayLike& learning_rates) {
           NNAdaptiveConfig<double> cfg;
           cfg.lambda = py_args::vector<6>(lambda_, "lambda_");
           cfg.kd = py_args::vector<6>(kd, "kd");
           cfg.gamma = py_args::scalar(gamma, "gamma");
           cfg.dt = py_args::scalar(dt, "dt");
           cfg.modification = parse_modification(modification);
           cfg.sigma_m = py_args::scalar(sigma_m, "sigma_m");
           cfg.kappa = py_args::scalar(kappa, "kappa");
           cfg.w_max = py_args::scalar(w_max, "w_max");
           cfg.dead_zone = py_args::scalar(dead_zone, "dead_zone");
           return make_nn(network, cfg, learning_rates);
         }),
         // The defaults are the config's, the one place they are written.
         py::arg("network"), py::arg("lambda_"), py::arg("kd"),
         py::arg("gamma") = NNAdaptiveConfig<double>{}.gamma,
         py::arg("dt") = NNAdaptiveConfig<double>{}.dt, py::kw_only(), py::arg("modification") = "none",
         py::arg("sigma_m") = 0.0, py::arg("kappa") = 0.0, py::arg("w_max") = 0.0,
         py::arg("dead_zone") = 0.0, py::arg("learning_rates") = py::none(),
         "network: an RbfNetwork with 24 inputs (copied; its weights are W(0)); lambda_: "
         "Lambda diagonal (6,), > 0; kd: K_d diagonal (6,), >= 0; gamma: Gamma_w = gamma I "
         "(the paper: 0.3); dt: control period [s] (the paper: 0.2). Robust modifications (off "
         "by default, as in the paper): modification = 'sigma' (sigma_m > 0), "
         "'e_modification' (kappa > 0) or 'projection' (||W||_F <= w_max); dead_zone: no "
         "adaptation while ||s|| < dead_zone. learning_rates (N,): per-centre Gamma_w.");
  def_common<NNController>(nn);
  def_copy<NNController>(nn);
  nn.def(py::pickle(&nn_state, &nn_from_state));
  nn.def_property(
        "weights", [](const NNController& c) { return Eigen::MatrixXd(c.weights()); },
        [](NNController& c, const typed::ArrayLike& w) {
          if (!c.set_weights(py_args::dynamic_matrix(w, "weights", 6, c.network().centres_count())))
            throw py::value_error("argument 'weights' is so large that its norm overflows");
        },
        "Current weights W, shape (6, N); assignable (warm start).")
      .def_property_readonly("weight_norm", &NNController::weight_norm, "||W||_F.")
      .def_property_readonly(
          "network_output", [](const NNController& c) { return Vec6(c.network_output()); },
          "W g(x) of the last step (before its update), shape (6,).")
      .def_property_readonly(
          "basis", [](const NNController& c) { return Eigen::VectorXd(c.basis()); },
          "g(x) of the last step, shape (N,).")
      .def_property_readonly("adapted", &NNController::adapted,
                             "Whether the last step moved the weights (False in the dead zone).")
      .def_property_readonly("n_centres",
                             [](const NNController& c) { return c.network().centres_count(); },
                             "Number of centres N.")
      .def_property_readonly(
          "centres", [](const NNController& c) { return Eigen::MatrixXd(c.network().centres()); },
          "Centres, shape (N, 24).")
      .def_property_readonly(
          "widths", [](const NNController& c) { return Eigen::VectorXd(c.network().widths()); },
          "Widths sigma_j, shape (N,).")
      .def_property_readonly(
          "input_offset",
          [](const NNController& c) { return Eigen::VectorXd(c.network().input_offset()); },
          "Input offset of the network's normalisation, shape (24,).")
      .def_property_readonly(
          "input_scale",
          [](const NNController& c) { return Eigen::VectorXd(c.network().input_scale()); },
          "Input scale of the network's normalisation, shape (24,).")
      .def_property_readonly(
          "modification",
          [](const NNController& c) { return std::string(to_string(c.config().modification)); },
          "The robust modification in use.");
}

void bind_controller(py::module_& m, TypeTag<LinController>) {
  // --- linear adaptive controller ---------------------------------------------
  py::class_<LinController> lin(
      m, "LinearAdaptiveController",
      "Linearly parameterised adaptive controller (eq. 26, 28; Fossen and Sagatun): tau = Phi "
      "theta_hat - J^T K_d s, theta_hat <- theta_hat - dt Gamma Phi^T J^-1 s. Knows NEROV's "
      "model structure (see regressor), not its parameters.");
  def_constructors(
      lin, "linear adaptive controller",
      "lambda_: Lambda diagonal (6,), > 0; kd: K_d diagonal (6,), >= 0; gamma: Gamma "
      "diagonal, a number or (24,), >= 0; dt: control period [s]; theta0: theta_hat(0) "
      "(24,), default zero (regressor_parameters(vehicle) gives the true one).",
      config_arg("lambda_", &LinConfig::lambda), config_arg("kd", &LinConfig::kd),
      config_arg("gamma", &LinConfig::gamma, &gamma_from),
      config_arg_or("dt", &LinConfig::dt, py::float_(LinConfig{}.dt)),
      config_arg_or("theta0", &LinConfig::theta0, py::none(), &theta0_from));
  def_common<LinController>(lin);
  def_controller_snapshot<LinController>(
      lin, "linear adaptive controller",
      [](const LinController& c, py::dict& d) {
        d["theta"] = ParameterVector<double>(c.theta());
        d["model_output"] = Vec6(c.model_output());
      },
      [](LinController& c, const py::dict& d, const TrackingError<double>& e, Status s) {
        return c.restore(
            e, s, py_args::vector<kRegressorParameters>(snapshot_field(d, "theta"), "theta"),
            model_output_from(d));
      });
  lin.def_property(
      "theta", [](const LinController& c) { return ParameterVector<double>(c.theta()); },
      [](LinController& c, const typed::ArrayLike& t) {
        c.set_theta(py_args::vector<kRegressorParameters>(t, "theta"));
      },
      "Current estimate theta_hat (24,); assignable.");
  def_model_output<LinController>(lin, "Phi theta_hat of the last step, shape (6,).");
}

void bind_controller(py::module_& m, TypeTag<PD>) {
  // --- PD ------------------------------------------------------------------
  py::class_<PD> pd(m, "PDController",
                    "PD baseline in the earth frame: tau = -J^T (K_p eta_tilde + K_d eta_tilde_dot).");
  def_constructors(pd, "PD controller", "kp, kd: diagonal gains (6,), >= 0.",
                   config_arg("kp", &PDConfig<double>::kp), config_arg("kd", &PDConfig<double>::kd));
  def_common<PD>(pd);
  def_controller_snapshot<PD>(
      pd, "PD controller", [](const PD&, py::dict&) {},
      [](PD& c, const py::dict&, const TrackingError<double>& e, Status s) {
        return c.restore(e, s);
      });
}

void bind_controller(py::module_& m, TypeTag<PID>) {
  // --- PID ------------------------------------------------------------------
  py::class_<PID> pid(
      m, "PIDController",
      "PID baseline in the earth frame with anti-windup: tau = -J^T (K_p eta_tilde + K_i z + "
      "K_d eta_tilde_dot), z the integral of eta_tilde, |K_i z| <= integral_limit per DOF and "
      "no integration further into the limit.");
  def_constructors(
      pid, "PID controller",
      "kp, ki, kd: diagonal gains (6,), >= 0; integral_limit: largest |K_i z| per DOF (6,), "
      "> 0 [N, N m]; dt: control period [s].",
      config_arg("kp", &PIDConfigD::kp), config_arg("ki", &PIDConfigD::ki),
      config_arg("kd", &PIDConfigD::kd), config_arg("integral_limit", &PIDConfigD::integral_limit),
      config_arg_or("dt", &PIDConfigD::dt, py::float_(PIDConfigD{}.dt)));
  def_common<PID>(pid);
  def_controller_snapshot<PID>(
      pid, "PID controller",
      [](const PID& c, py::dict& d) { d["integral"] = Vec6(c.integral()); },
      [](PID& c, const py::dict& d, const TrackingError<double>& e, Status s) {
        return c.restore(e, s, py_args::vector<6>(snapshot_field(d, "integral"), "integral"));
      });
  pid.def_property_readonly(
      "integral", [](const PID& c) { return Vec6(c.integral()); },
      "The integrator state z (6,), the limited time integral of eta_tilde.");
}

void bind_controller(py::module_& m, TypeTag<SMC>) {
  // --- sliding mode -----------------------------------------------------------
  py::class_<SMC> smc(
      m, "SlidingModeController",
      "Sliding-mode controller with a boundary layer: tau = Phi theta - J^T (K_d s + K "
      "sat(s / phi)), with theta the nominal model's parameters (regressor).");
  def_constructors(
      smc, "sliding-mode controller",
      "lambda_: Lambda (6,), > 0; kd: K_d (6,), >= 0; k: switching gain (6,), >= 0; phi: "
      "boundary-layer width (6,), > 0; theta: the nominal model (24,), e.g. "
      "regressor_parameters(vehicle).",
      config_arg("lambda_", &SMCConfig::lambda), config_arg("kd", &SMCConfig::kd),
      config_arg("k", &SMCConfig::k), config_arg("phi", &SMCConfig::phi),
      config_arg("theta", &SMCConfig::theta));
  def_common<SMC>(smc);
  def_model_controller<SMC>(smc, "sliding-mode controller",
                           "The nominal model's f of the last step, shape (6,).");
}

void bind_controller(py::module_& m, TypeTag<CT>) {
  // --- computed torque ---------------------------------------------------------
  py::class_<CT> ct(
      m, "ComputedTorqueController",
      "Computed-torque (inverse-dynamics) controller on a nominal vehicle: tau = M nu_r_dot + "
      "C(nu) nu_r + D(nu) nu_r + g(eta) - J^T K_d s, with the vehicle's own M, C, D and g.");
  def_init_from_config<CT>(ct, "computed-torque controller");
  ct.def(py::init([](const Vehicle<double>& vehicle, const typed::ArrayLike& lambda_, const typed::ArrayLike& kd) {
           ComputedTorqueConfig<double> cfg;
           cfg.vehicle = vehicle.parameters();
           cfg.lambda = py_args::vector<6>(lambda_, "lambda_");
           cfg.kd = py_args::vector<6>(kd, "kd");
           return from_config<CT>(cfg, "computed-torque controller");
         }),
         py::arg("vehicle"), py::arg("lambda_"), py::arg("kd"),
         "vehicle: the nominal model (its parameters are copied); lambda_: Lambda (6,), > 0; "
         "kd: K_d (6,), >= 0.");
  def_common<CT>(ct);
  def_model_controller<CT>(
      ct, "computed-torque controller",
      "M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) of the last step, shape (6,).");
}

template <typename Controller>
void bind_controller(py::module_& m, TypeTag<Controller>) {
  bind_generic_controller<Controller>(m);
}

void bind_controllers(py::module_& m) {
  // Every class also says what it is in a scenario file, and
  // BUILT_IN_CONTROLLERS maps those type names to the classes: the Python
  // registry and the choice of the all-C++ loop read it.
  py::dict built_in;
  for_each_type(BuiltInControllers<double>{}, [&m, &built_in](auto tag) {
    using Controller = typename decltype(tag)::type;
    bind_controller(m, tag);
    py::object cls = py::type::of<Controller>();
    cls.attr("type_name") = Controller::kTypeName;
    cls.attr("title") = Controller::kTitle;
    cls.attr("Config") = py::type::of<typename Controller::Config>();
    built_in[Controller::kTypeName] = cls;
  });
  m.attr("BUILT_IN_CONTROLLERS") = built_in;
}

}  // namespace neurov::bindings
