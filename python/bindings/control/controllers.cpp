// The controllers: every built-in one bound from its header by
// generic_controller.hpp; here what two of them have besides (the NN's
// network and weights, the linear adaptive's theta_hat).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "bindings.hpp"
#include "controller_bindings.hpp"
#include "ardusub_bindings.hpp"
#include "generic_controller.hpp"
#include "neurov/control/linear_adaptive_controller.hpp"
#include "neurov/control/nn_controller.hpp"
#include "neurov/control/rbf_network.hpp"
#include "neurov/model/regressor.hpp"
#include "numpy_args.hpp"
#include "snapshot.hpp"

namespace neurov::bindings {

namespace py = pybind11;
using Vec6 = Vector6<double>;
using Network = RbfNetwork<double>;  // dynamic inputs and centres
using NNController = NNAdaptiveController<double>;
using LinController = LinearAdaptiveController<double>;

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
  network_state(c.network(), d);
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
  NNController::Network network = network_from_state<NNController::Network>(d, kNNInputs, "network");
  const Eigen::Index n = network.centres_count();
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
                    snapshot_vector<6>(d, "network_output"),
                    snapshot_field(d, "adapted").cast<bool>()),
      "NN controller");
  return c;
}

}  // namespace

void bind_controller(py::module_& m, TypeTag<NNController>) {
  py::class_<NNController> nn(m, NNController::kClassName, NNController::kDoc);
  nn.def(py::init(&make_nn), py::arg("network"), py::arg("config"), py::kw_only(),
         py::arg("learning_rates") = py::none(),
         "network: an RbfNetwork with 24 inputs (copied; its weights are W(0)); config: an "
         "NNAdaptiveConfig; learning_rates (N,): per-centre Gamma_w.");
  def_keyword_init(nn,
                   keyword_doc<NNController>("network: an RbfNetwork with 24 inputs (copied; its "
                                             "weights are W(0)); learning_rates (N,): per-centre "
                                             "Gamma_w. "),
                   &make_nn, extra_args<Network>(py::arg("network")),
                   extra_args<typed::OptionalArrayLike>(py::arg("learning_rates") = py::none()));
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
      .def_property_readonly(
          "modification",
          [](const NNController& c) { return std::string(to_string(c.config().modification)); },
          "The robust modification in use.");
  def_network_views(nn, [](const NNController& c) -> const NNController::Network& { return c.network(); });
}

void bind_controller(py::module_& m, TypeTag<LinController>) {
  py::class_<LinController> lin = bind_controller_class<LinController>(m);
  def_controller_snapshot<LinController>(
      lin, LinController::kWhat,
      [](const LinController& c, py::dict& d) {
        d["theta"] = ParameterVector<double>(c.theta());
        d["model_output"] = Vec6(c.model_output());
      },
      [](LinController& c, const py::dict& d, const TrackingError<double>& e, Status s) {
        return c.restore(
            e, s, snapshot_vector<kRegressorParameters>(d, "theta"),
            snapshot_vector<6>(d, "model_output"));
      });
  lin.def_property(
      "theta", [](const LinController& c) { return ParameterVector<double>(c.theta()); },
      [](LinController& c, const typed::ArrayLike& t) {
        c.set_theta(py_args::vector<kRegressorParameters>(t, "theta"));
      },
      "Current estimate theta_hat (24,); assignable.");
  def_state<LinController>(lin);
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
