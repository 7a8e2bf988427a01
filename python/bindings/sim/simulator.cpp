// neurov/sim/simulator.hpp in Python: a run stepped from Python, one control
// period per step(), with the controller outside.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/typing.h>

#include <cstdint>
#include <stdexcept>
#include <string>

#include "bindings.hpp"
#include "numpy_args.hpp"
#include "neurov/sim/simulator.hpp"
#include "result.hpp"

namespace neurov::bindings {

namespace py = pybind11;

namespace {

using Sim = Simulator<double>;
using Obs = Observation<double>;

/// A vector of length 6 that may hold NaN (a refused step's force or s).
Vector6<double> any_vector6(const py::handle& v, const char* name) {
  return Eigen::Map<const Vector6<double>>(py_args::real_rows(v, name, 6, -1, false).data());
}

Status step(Sim& sim, const typed::ArrayLike& tau_in, Status status, const typed::OptionalArrayLike& s_in,
            double adaptive_norm, const typed::OptionalArrayLike& parameters_in) {
  if (sim.done()) {
    const std::string why = sim.diverged() ? "the plant diverged at t = " +
                                                 py_args::num(sim.observation().t)
                                           : "all " + std::to_string(sim.steps()) +
                                                 " rows are simulated";
    throw std::runtime_error("Simulator.step: the run is done (" + why +
                             "); result() holds every row, reset() starts again");
  }
  if (sim.log_full())
    throw std::runtime_error("Simulator.step: the log window of " + std::to_string(sim.log_rows()) +
                             " rows is full; drain() hands its rows over and empties it");
  // A refused step's force is not applied, so it may be anything of shape (6,).
  const Vector6<double> tau =
      status == Status::ok ? py_args::vector<6>(tau_in, "tau") : any_vector6(tau_in, "tau");
  ControllerReport<double> report;
  report.status = status;
  if (!s_in.is_none()) report.s = any_vector6(s_in, "s");
  report.adaptive_norm = adaptive_norm;
  Eigen::VectorXd parameters;
  if (!parameters_in.is_none())
    parameters = py_args::dynamic_vector(parameters_in, "parameters", sim.logged_parameters());
  if (parameters.size() != sim.logged_parameters())
    throw py::value_error("argument 'parameters' must have shape (" +
                          std::to_string(sim.logged_parameters()) +
                          ",) (the simulator's logged_parameters), got None");
  report.parameters = parameters.data();
  report.parameter_count = static_cast<int>(parameters.size());
  return sim.step(tau, report);
}

}  // namespace

void bind_simulator(py::module_& m) {
  py::class_<Obs>(m, "Observation",
                  "What a controller is given at t_k: the measured pose and velocity (noise "
                  "and sensor faults applied; NaN in a dropout) and the desired state.")
      .def(py::init([](double t, const typed::ArrayLike& eta, const typed::ArrayLike& nu,
                       const typed::ArrayLike& eta_d, const typed::ArrayLike& eta_d_dot,
                       const typed::ArrayLike& eta_d_ddot) {
             Obs o;
             o.t = t;
             o.eta = any_vector6(eta, "eta");
             o.nu = any_vector6(nu, "nu");
             o.desired.eta_d = py_args::vector<6>(eta_d, "eta_d");
             o.desired.eta_d_dot = py_args::vector<6>(eta_d_dot, "eta_d_dot");
             o.desired.eta_d_ddot = py_args::vector<6>(eta_d_ddot, "eta_d_ddot");
             return o;
           }),
           py::arg("t"), py::arg("eta"), py::arg("nu"), py::arg("eta_d"), py::arg("eta_d_dot"),
           py::arg("eta_d_ddot"),
           "An observation, e.g. to test a controller (eta and nu may hold NaN, as in a "
           "dropout).")
      .def_property_readonly("t", [](const Obs& o) { return o.t; }, "Time t_k [s].")
      .def_property_readonly("eta", [](const Obs& o) { return o.eta; }, "Measured pose (6,).")
      .def_property_readonly("nu", [](const Obs& o) { return o.nu; },
                             "Measured body velocity (6,).")
      .def_property_readonly("eta_d", [](const Obs& o) { return o.desired.eta_d; },
                             "Desired pose (6,).")
      .def_property_readonly("eta_d_dot", [](const Obs& o) { return o.desired.eta_d_dot; },
                             "Its first time derivative (6,).")
      .def_property_readonly("eta_d_ddot", [](const Obs& o) { return o.desired.eta_d_ddot; },
                             "Its second time derivative (6,).")
      .def("__repr__", [](const Obs& o) { return "Observation(t=" + py_args::num(o.t) + ")"; });

  py::class_<Sim>(m, "Simulator",
                  "Everything of a run except the controller, stepped one control period at "
                  "a time: the same rows as run_closed_loop for the same forces.")
      .def(py::init([](const Vehicle<double>& vehicle, const SimulationConfig<double>& config,
                       int logged_parameters, Eigen::Index log_rows) {
             Sim sim;
             py_args::raise_if_invalid(
                 Sim::create(vehicle, config, sim, logged_parameters, log_rows),
                 "SimulationConfig");
             return sim;
           }),
           py::arg("vehicle"), py::arg("config"), py::arg("logged_parameters") = 0,
           py::arg("log_rows") = 0,
           "Copies the vehicle and the configuration; `logged_parameters` is the number of "
           "parameters step() logs per row (the result's theta columns); `log_rows` > 0 keeps "
           "a window of at most that many rows, emptied by drain() (0: every row of the run). "
           "Raises ValueError naming a bad field.")
      .def(
          "reset",
          [](Sim& sim, const typed::OptionalIndex& seed) {
            if (seed.is_none()) {
              sim.reset();
              return;
            }
            if (!py::isinstance<py::int_>(seed) || py::isinstance<py::bool_>(seed))
              throw py::type_error("argument 'seed' must be an int or None");
            // SimulationConfig::seed's type: every seed a configuration takes resets too.
            sim.reset(py_args::integer<std::uint64_t>(seed, "argument 'seed'"));
          },
          py::arg("seed") = py::none(),
          "Back to t = 0 with noise from `seed`; None: the seed of the last reset (the "
          "configuration's at first), so the same run again.")
      .def_property_readonly(
          "observation", [](const Sim& sim) { return sim.observation(); },
          "What the controller is to be given at t_k = steps * dt (an Observation).")
      .def("step", &step, py::arg("tau"), py::arg_v("status", Status::ok, "Status.ok"),
           py::arg("s") = py::none(), py::arg("adaptive_norm") = 0.0,
           py::arg("parameters") = py::none(),
           "Logs row k with the force tau (6,) and the controller's report (status: "
           "anything but ok is a refused step and the refused-step policy decides the force; "
           "s, adaptive_norm and `parameters` (logged_parameters,) are logged) and advances "
           "one control period. Returns the plant's Status. tau must be finite when status "
           "is ok. After done, raises RuntimeError and changes nothing.")
      .def_property_readonly("done", &Sim::done, "Every row simulated, or the plant diverged.")
      .def_property_readonly("diverged", &Sim::diverged,
                             "The plant diverged: the run stopped at its last row (done).")
      .def_property_readonly("steps", &Sim::steps, "Rows logged so far.")
      .def_property_readonly("planned_steps", &Sim::planned_steps,
                             "Rows of a whole run: round(duration / dt) + 1.")
      .def_property_readonly("logged_parameters", &Sim::logged_parameters,
                             "Parameters step() logs per row (the result's theta columns).")
      .def_property_readonly("faults", &Sim::faults,
                             "fault_bits of the sensor faults and pitch limit in the observation.")
      .def_property_readonly(
          "state",
          [](const Sim& sim) {
            return py::make_tuple(Vector6<double>(sim.eta()), Vector6<double>(sim.nu()));
          },
          "The true (eta, nu) at t_k.")
      .def_property_readonly(
          "config", [](const Sim& sim) { return sim.config(); }, "A copy of the configuration.")
      .def_property_readonly(
          "estimate_covariance",
          [](const Sim& sim) -> py::typing::Optional<Ekf<double>::StateMatrix> {
            if (sim.config().estimator.type != EstimatorType::ekf || !sim.sensing().active())
              return py::none();
            return py::cast(Ekf<double>::StateMatrix(sim.sensing().filter().covariance()));
          },
          "The EKF's covariance (15, 15) at t_k (position, angles, body velocity, rates, gyro "
          "bias), or None without the ekf estimator.")
      .def_property_readonly("log_rows", &Sim::log_rows,
                             "Rows the log holds at most (the whole run, or the window).")
      .def_property_readonly("logged_from", &Sim::logged_from,
                             "The run's index of the log's first row (rows drained before).")
      .def_property_readonly("log_full", &Sim::log_full,
                             "The log window is full: step() refuses until drain().")
      .def(
          "result", [](const Sim& sim) { return result_dict(sim.result()); },
          "The rows in the log (logged so far, or since the last drain), as the dict "
          "run_closed_loop returns.")
      .def(
          "drain",
          [](Sim& sim) {
            SimulationResult<double> rows;
            sim.drain(rows);
            return result_dict(std::move(rows));
          },
          "The rows in the log, as result() gives them, and empties the log so that "
          "stepping goes on past a full window.");
}

}  // namespace neurov::bindings
