#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <tuple>

#include "bindings.hpp"
#include "neurov/control/linear_adaptive_controller.hpp"
#include "neurov/control/nn_controller.hpp"
#include "neurov/control/pd_controller.hpp"
#include "neurov/control/pid_controller.hpp"
#include "neurov/control/rbf_network.hpp"
#include "neurov/control/reference_model.hpp"
#include "neurov/model/regressor.hpp"
#include "neurov/control/sliding_mode_controller.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/model/vehicle.hpp"
#include "numpy_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;
using Vec6 = Vector6<double>;
using Network = RbfNetwork<double>;  // dynamic inputs and centres
using NNController = NNAdaptiveController<double>;
using LinController = LinearAdaptiveController<double>;
using PD = PDController<double>;
using PID = PIDController<double>;
using SMC = SlidingModeController<double>;

namespace {

void raise_step_status(Status s) {
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

py::dict tracking_dict(const TrackingError<double>& e) {
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
Vec6 checked_step(Controller& c, py::handle eta, py::handle nu, py::handle eta_d,
                  py::handle eta_d_dot, py::handle eta_d_ddot) {
  const Vec6 e = py_args::vector<6>(eta, "eta");
  const Vec6 n = py_args::vector<6>(nu, "nu");
  const Vec6 ed = py_args::vector<6>(eta_d, "eta_d");
  const Vec6 edd = py_args::vector<6>(eta_d_dot, "eta_d_dot");
  const Vec6 eddd = py_args::vector<6>(eta_d_ddot, "eta_d_ddot");
  Vec6 tau;
  raise_step_status(c.step(e, n, ed, edd, eddd, tau));
  return tau;
}

constexpr const char* kStepDoc =
    "One control step from the measured pose eta (6,) and body velocity nu (6,) and the "
    "desired eta_d, eta_d_dot, eta_d_ddot (6,) in the earth frame; returns tau (6,), the body "
    "forces and moments. A NaN/Inf input, or the pitch singularity, raises ValueError and "
    "leaves the controller exactly as it was.";

template <typename Controller, typename Class>
void def_common(Class& cls) {
  cls.def("step", &checked_step<Controller>, py::arg("eta"), py::arg("nu"), py::arg("eta_d"),
          py::arg("eta_d_dot"), py::arg("eta_d_ddot"), kStepDoc)
      .def("reset", &Controller::reset, "Back to the initial state and a zero history.")
      .def_property_readonly(
          "s", [](const Controller& c) { return Vec6(c.tracking().s); },
          "Filtered tracking error s of the last step, shape (6,).")
      .def_property_readonly(
          "tracking", [](const Controller& c) { return tracking_dict(c.tracking()); },
          "Tracking error and virtual reference of the last step: a dict of (6,) arrays "
          "eta_tilde, eta_tilde_dot, s, eta_r_dot, eta_r_ddot, nu_r, nu_r_dot.");
}

RobustModification parse_modification(py::handle obj) {
  const auto s =
      py_args::choice(obj, "modification", {"none", "sigma", "e_modification", "projection"});
  for (auto m : {RobustModification::sigma, RobustModification::e_modification,
                 RobustModification::projection})
    if (s == to_string(m)) return m;
  return RobustModification::none;
}

Eigen::VectorXd widths_arg(py::handle width, Eigen::Index n) {
  if (py::isinstance<py::float_>(width) || py::isinstance<py::int_>(width))
    return Eigen::VectorXd::Constant(n, py_args::scalar(width, "width"));
  return py_args::dynamic_vector(width, "width", n);
}

}  // namespace

void bind_controllers(py::module_& m) {
  // --- reference model -----------------------------------------------------
  py::class_<ReferenceModel<double>>(
      m, "ReferenceModel",
      "Reference model of eq. 12-13: nu_d_dot = -Lambda_d nu_d + J^T(eta_d) Omega (r - eta_d), "
      "eta_d_dot = J(eta_d) nu_d. Turns a commanded pose r into a smooth desired trajectory.")
      .def(py::init([](py::handle lambda_d, py::handle omega, py::handle eta0) {
             const Vec6 ld = py_args::vector<6>(lambda_d, "lambda_d");
             const Vec6 om = py_args::vector<6>(omega, "omega");
             const Vec6 e0 = eta0.is_none() ? Vec6::Zero() : py_args::vector<6>(eta0, "eta0");
             ReferenceModel<double> r;
             py_args::raise_if_invalid(ReferenceModel<double>::create(ld, om, e0, r),
                                       "reference model");
             return r;
           }),
           py::arg("lambda_d"), py::arg("omega"), py::arg("eta0") = py::none(),
           "lambda_d: damping diagonal (6,), > 0; omega: stiffness diagonal (6,), > 0; eta0: "
           "initial pose (6,), default zero. Starts at rest.")
      .def(
          "step",
          [](ReferenceModel<double>& r, py::handle cmd, py::handle dt) {
            const Vec6 rc = py_args::vector<6>(cmd, "r");
            const double h = py_args::positive(dt, "dt");
            DesiredState<double> d;
            const Status s = r.step(rc, h, d);
            if (s != Status::ok) raise_step_status(s);
            return std::make_tuple(Vec6(d.eta_d), Vec6(d.eta_d_dot), Vec6(d.eta_d_ddot));
          },
          py::arg("r"), py::arg("dt"),
          "Advances by dt with the commanded pose r (6,) held (RK4); returns (eta_d, eta_d_dot, "
          "eta_d_ddot). A refused step raises ValueError and changes nothing.")
      .def(
          "reset",
          [](ReferenceModel<double>& r, py::handle eta0) {
            r.reset(py_args::vector<6>(eta0, "eta0"));
          },
          py::arg("eta0"), "Back to rest at eta0 (6,).")
      .def_property_readonly("eta_d", [](const ReferenceModel<double>& r) { return Vec6(r.eta_d()); },
                             "Current desired pose (6,).")
      .def_property_readonly("nu_d", [](const ReferenceModel<double>& r) { return Vec6(r.nu_d()); },
                             "Current desired body velocity (6,).")
      .def_property_readonly("lambda_d",
                             [](const ReferenceModel<double>& r) { return Vec6(r.lambda_d()); },
                             "Damping diagonal (6,).")
      .def_property_readonly("omega", [](const ReferenceModel<double>& r) { return Vec6(r.omega()); },
                             "Stiffness diagonal (6,).")
      .def_property_readonly(
          "pitch_limited", [](const ReferenceModel<double>& r) { return r.pitch_limited(); },
          "True when the last accepted step limited the pitch to +-(pi/2 - 0.2) rad: the "
          "command's (clamped) or the reference's own (held at the limit). Such a step is taken "
          "and returns normally. False after construction and reset().");

  // --- tracking error and regressor ----------------------------------------
  m.def(
      "tracking_error",
      [](py::handle eta, py::handle nu, py::handle eta_d, py::handle eta_d_dot,
         py::handle eta_d_ddot, py::handle lambda_) {
        TrackingError<double> e;
        const Status s = compute_tracking_error<double>(
            py_args::vector<6>(eta, "eta"), py_args::vector<6>(nu, "nu"),
            py_args::vector<6>(eta_d, "eta_d"), py_args::vector<6>(eta_d_dot, "eta_d_dot"),
            py_args::vector<6>(eta_d_ddot, "eta_d_ddot"), py_args::vector<6>(lambda_, "lambda_"),
            e);
        raise_step_status(s);
        return tracking_dict(e);
      },
      py::arg("eta"), py::arg("nu"), py::arg("eta_d"), py::arg("eta_d_dot"), py::arg("eta_d_ddot"),
      py::arg("lambda_"),
      "Tracking error and virtual reference (eq. 11, 14-16) with the diagonal Lambda (6,): a "
      "dict of (6,) arrays eta_tilde, eta_tilde_dot, s, eta_r_dot, eta_r_ddot, nu_r, nu_r_dot.");

  m.def(
      "regressor",
      [](py::handle nu_r_dot, py::handle nu_r, py::handle nu, py::handle eta) {
        const Vec6 e = py_args::vector<6>(eta, "eta");
        return RegressorMatrix<double>(regressor<double>(
            py_args::vector<6>(nu_r_dot, "nu_r_dot"), py_args::vector<6>(nu_r, "nu_r"),
            py_args::vector<6>(nu, "nu"), std::sin(e(3)), std::cos(e(3)), std::sin(e(4)),
            std::cos(e(4))));
      },
      py::arg("nu_r_dot"), py::arg("nu_r"), py::arg("nu"), py::arg("eta"),
      "Regressor Phi (6, 24) with Phi @ theta = M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) "
      "for NEROV's model structure; THETA_NAMES names the columns.");

  m.def(
      "regressor_parameters",
      [](const Vehicle<double>& v) {
        ParameterVector<double> theta;
        py_args::raise_if_invalid(regressor_parameters(v.parameters(), theta), "vehicle");
        return theta;
      },
      py::arg("vehicle"),
      "The true theta (24,) of a vehicle whose structure the regressor covers (r_g = 0, "
      "diagonal inertia and added mass, r_b on the z axis); ValueError otherwise.");

  py::list names;
  for (int i = 0; i < kRegressorParameters; ++i) names.append(theta_name(i));
  m.attr("THETA_NAMES") = py::tuple(names);

  // --- RBF network -----------------------------------------------------------
  py::class_<Network>(m, "RbfNetwork",
                      "Radial-basis-function network (eq. 30): g_j(x) = exp(-||x_hat - xi_j||^2 / "
                      "(2 sigma_j^2)), output W g(x) with W (6, N); x_hat = (x - input_offset) * "
                      "input_scale.")
      .def(py::init([](py::handle centres, py::handle width, py::handle input_offset,
                       py::handle input_scale) {
             const Eigen::MatrixXd c = py_args::dynamic_matrix(centres, "centres", -1, -1);
             if (c.rows() < 1 || c.cols() < 1)
               throw py::value_error("argument 'centres' must have at least one row and column");
             const Eigen::VectorXd w = widths_arg(width, c.rows());
             const Eigen::VectorXd off = input_offset.is_none()
                                             ? Eigen::VectorXd::Zero(c.cols())
                                             : py_args::dynamic_vector(input_offset, "input_offset",
                                                                       c.cols());
             const Eigen::VectorXd sc = input_scale.is_none()
                                            ? Eigen::VectorXd::Ones(c.cols())
                                            : py_args::dynamic_vector(input_scale, "input_scale",
                                                                      c.cols());
             Network n;
             py_args::raise_if_invalid(Network::create(c, w, off, sc, n), "RBF network");
             return n;
           }),
           py::arg("centres"), py::arg("width"), py::arg("input_offset") = py::none(),
           py::arg("input_scale") = py::none(),
           "centres: (N, n_in) array, one centre per row; width: sigma for every centre, or "
           "(N,) per centre, > 0; input_offset and input_scale: (n_in,) input normalisation, "
           "default identity (the paper's choice). Weights start at zero.")
      .def(
          "basis",
          [](const Network& n, py::handle x) {
            const Eigen::VectorXd xv = py_args::dynamic_vector(x, "x", n.inputs());
            Eigen::VectorXd g(n.centres_count());
            n.basis(xv, g);
            return g;
          },
          py::arg("x"), "Basis values g(x), shape (N,).")
      .def(
          "output",
          [](const Network& n, py::handle x) {
            const Eigen::VectorXd xv = py_args::dynamic_vector(x, "x", n.inputs());
            Eigen::VectorXd g(n.centres_count());
            Eigen::Matrix<double, 6, 1> y;
            n.output(xv, g, y);
            return Vec6(y);
          },
          py::arg("x"), "Network output W g(x), shape (6,).")
      .def_property(
          "weights", [](const Network& n) { return Eigen::MatrixXd(n.weights()); },
          [](Network& n, py::handle w) {
            const Eigen::MatrixXd wm = py_args::dynamic_matrix(w, "weights", 6, n.centres_count());
            n.set_weights(wm);
          },
          "Output weights W, shape (6, N); assignable.")
      .def_property_readonly("centres", [](const Network& n) { return Eigen::MatrixXd(n.centres()); },
                             "Centres, shape (N, n_in).")
      .def_property_readonly("widths", [](const Network& n) { return Eigen::VectorXd(n.widths()); },
                             "Widths sigma_j, shape (N,).")
      .def_property_readonly("input_offset",
                             [](const Network& n) { return Eigen::VectorXd(n.input_offset()); },
                             "Input offset, shape (n_in,).")
      .def_property_readonly("input_scale",
                             [](const Network& n) { return Eigen::VectorXd(n.input_scale()); },
                             "Input scale, shape (n_in,).")
      .def_property_readonly("n_inputs", &Network::inputs, "Number of inputs n_in.")
      .def_property_readonly("n_centres", &Network::centres_count, "Number of centres N.");

  // --- NN adaptive controller -------------------------------------------------
  py::class_<NNController> nn(
      m, "NNAdaptiveController",
      "Direct adaptive RBF-network controller (eq. 35, 37): tau = W g(x) - J^T K_d s with "
      "x = [nu_r_dot; nu_r; nu; eta] (24 inputs), then W <- W - dt (J^-1 s) g(x)^T Gamma_w. "
      "tau uses the weights from before the update.");
  nn.def(py::init([](const Network& network, py::handle lambda_, py::handle kd, py::handle gamma,
                     py::handle dt, py::handle modification, py::handle sigma_m, py::handle kappa,
                     py::handle w_max, py::handle dead_zone, py::handle learning_rates) {
           if (network.inputs() != kNNInputs)
             throw py::value_error("argument 'network' must have 24 inputs ([nu_r_dot; nu_r; "
                                   "nu; eta]), got " + std::to_string(network.inputs()));
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
           NNController::Network fixed_inputs;
           py_args::raise_if_invalid(
               NNController::Network::create(network.centres(), network.widths(),
                                             network.input_offset(), network.input_scale(),
                                             fixed_inputs),
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
         }),
         py::arg("network"), py::arg("lambda_"), py::arg("kd"), py::arg("gamma") = 0.3,
         py::arg("dt") = 0.2, py::kw_only(), py::arg("modification") = "none",
         py::arg("sigma_m") = 0.0, py::arg("kappa") = 0.0, py::arg("w_max") = 0.0,
         py::arg("dead_zone") = 0.0, py::arg("learning_rates") = py::none(),
         "network: an RbfNetwork with 24 inputs (copied; its weights are W(0)); lambda_: "
         "Lambda diagonal (6,), > 0; kd: K_d diagonal (6,), >= 0; gamma: Gamma_w = gamma I "
         "(the paper: 0.3); dt: control period [s] (the paper: 0.2). Robust modifications (off "
         "by default, as in the paper): modification = 'sigma' (sigma_m > 0), "
         "'e_modification' (kappa > 0) or 'projection' (||W||_F <= w_max); dead_zone: no "
         "adaptation while ||s|| < dead_zone. learning_rates (N,): per-centre Gamma_w.");
  def_common<NNController>(nn);
  nn.def_property(
        "weights", [](const NNController& c) { return Eigen::MatrixXd(c.weights()); },
        [](NNController& c, py::handle w) {
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
          "modification",
          [](const NNController& c) { return std::string(to_string(c.config().modification)); },
          "The robust modification in use.");

  // --- linear adaptive controller ---------------------------------------------
  py::class_<LinController> lin(
      m, "LinearAdaptiveController",
      "Linearly parameterised adaptive controller (eq. 26, 28; Fossen and Sagatun): tau = Phi "
      "theta_hat - J^T K_d s, theta_hat <- theta_hat - dt Gamma Phi^T J^-1 s. Knows NEROV's "
      "model structure (see regressor), not its parameters.");
  lin.def(py::init([](py::handle lambda_, py::handle kd, py::handle gamma, py::handle dt,
                      py::handle theta0) {
            LinearAdaptiveConfig<double> cfg;
            cfg.lambda = py_args::vector<6>(lambda_, "lambda_");
            cfg.kd = py_args::vector<6>(kd, "kd");
            if (py::isinstance<py::float_>(gamma) || py::isinstance<py::int_>(gamma))
              cfg.gamma.setConstant(py_args::scalar(gamma, "gamma"));
            else
              cfg.gamma = py_args::vector<kRegressorParameters>(gamma, "gamma");
            cfg.dt = py_args::scalar(dt, "dt");
            cfg.theta0 = theta0.is_none() ? ParameterVector<double>::Zero()
                                          : py_args::vector<kRegressorParameters>(theta0, "theta0");
            LinController c;
            py_args::raise_if_invalid(LinController::create(cfg, c), "linear adaptive controller");
            return c;
          }),
          py::arg("lambda_"), py::arg("kd"), py::arg("gamma"), py::arg("dt") = 0.2,
          py::arg("theta0") = py::none(),
          "lambda_: Lambda diagonal (6,), > 0; kd: K_d diagonal (6,), >= 0; gamma: Gamma "
          "diagonal, a number or (24,), >= 0; dt: control period [s]; theta0: theta_hat(0) "
          "(24,), default zero (regressor_parameters(vehicle) gives the true one).");
  def_common<LinController>(lin);
  lin.def_property(
         "theta", [](const LinController& c) { return ParameterVector<double>(c.theta()); },
         [](LinController& c, py::handle t) {
           c.set_theta(py_args::vector<kRegressorParameters>(t, "theta"));
         },
         "Current estimate theta_hat (24,); assignable.")
      .def_property_readonly(
          "model_output", [](const LinController& c) { return Vec6(c.model_output()); },
          "Phi theta_hat of the last step, shape (6,).");

  // --- PD ------------------------------------------------------------------
  py::class_<PD> pd(m, "PDController",
                    "PD baseline in the earth frame: tau = -J^T (K_p eta_tilde + K_d eta_tilde_dot).");
  pd.def(py::init([](py::handle kp, py::handle kd) {
           PDConfig<double> cfg;
           cfg.kp = py_args::vector<6>(kp, "kp");
           cfg.kd = py_args::vector<6>(kd, "kd");
           PD c;
           py_args::raise_if_invalid(PD::create(cfg, c), "PD controller");
           return c;
         }),
         py::arg("kp"), py::arg("kd"), "kp, kd: diagonal gains (6,), >= 0.");
  def_common<PD>(pd);

  // --- PID ------------------------------------------------------------------
  py::class_<PID> pid(
      m, "PIDController",
      "PID baseline in the earth frame with anti-windup: tau = -J^T (K_p eta_tilde + K_i z + "
      "K_d eta_tilde_dot), z the integral of eta_tilde, |K_i z| <= integral_limit per DOF and "
      "no integration further into the limit.");
  pid.def(py::init([](py::handle kp, py::handle ki, py::handle kd, py::handle integral_limit,
                      py::handle dt) {
            PIDConfig<double> cfg;
            cfg.kp = py_args::vector<6>(kp, "kp");
            cfg.ki = py_args::vector<6>(ki, "ki");
            cfg.kd = py_args::vector<6>(kd, "kd");
            cfg.integral_limit = py_args::vector<6>(integral_limit, "integral_limit");
            cfg.dt = py_args::scalar(dt, "dt");
            PID c;
            py_args::raise_if_invalid(PID::create(cfg, c), "PID controller");
            return c;
          }),
          py::arg("kp"), py::arg("ki"), py::arg("kd"), py::arg("integral_limit"),
          py::arg("dt") = 0.2,
          "kp, ki, kd: diagonal gains (6,), >= 0; integral_limit: largest |K_i z| per DOF (6,), "
          "> 0 [N, N m]; dt: control period [s].");
  def_common<PID>(pid);
  pid.def_property_readonly(
      "integral", [](const PID& c) { return Vec6(c.integral()); },
      "The integrator state z (6,), the limited time integral of eta_tilde.");

  // --- sliding mode -----------------------------------------------------------
  py::class_<SMC> smc(
      m, "SlidingModeController",
      "Sliding-mode controller with a boundary layer: tau = Phi theta - J^T (K_d s + K "
      "sat(s / phi)), with theta the nominal model's parameters (regressor).");
  smc.def(py::init([](py::handle lambda_, py::handle kd, py::handle k, py::handle phi,
                      py::handle theta) {
            SlidingModeConfig<double> cfg;
            cfg.lambda = py_args::vector<6>(lambda_, "lambda_");
            cfg.kd = py_args::vector<6>(kd, "kd");
            cfg.k = py_args::vector<6>(k, "k");
            cfg.phi = py_args::vector<6>(phi, "phi");
            cfg.theta = py_args::vector<kRegressorParameters>(theta, "theta");
            SMC c;
            py_args::raise_if_invalid(SMC::create(cfg, c), "sliding-mode controller");
            return c;
          }),
          py::arg("lambda_"), py::arg("kd"), py::arg("k"), py::arg("phi"), py::arg("theta"),
          "lambda_: Lambda (6,), > 0; kd: K_d (6,), >= 0; k: switching gain (6,), >= 0; phi: "
          "boundary-layer width (6,), > 0; theta: the nominal model (24,), e.g. "
          "regressor_parameters(vehicle).");
  def_common<SMC>(smc);
  smc.def_property_readonly(
      "model_output", [](const SMC& c) { return Vec6(c.model_output()); },
      "The nominal model's f of the last step, shape (6,).");
}

}  // namespace neurov::bindings
