// The built-in closed loop: a Simulator driven by one of neurov's controllers,
// all in C++ so that a whole run is one call. The same code path as a run
// driven step by step from outside (simulator.hpp).
#pragma once

#include <Eigen/Core>

#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/regressor.hpp"
#include "neurov/model/vehicle.hpp"
#include "neurov/sim/config.hpp"
#include "neurov/sim/result.hpp"
#include "neurov/sim/simulator.hpp"

namespace neurov {

/// The most parameters a built-in controller logs per step.
constexpr int kMaxLoggedParameters = kRegressorParameters;

/// The report of a controller's last step: its status, s, adaptive norm and
/// logged parameters (copied into `parameters`, which the report points to).
/// The one place that asks a controller for its diagnostics.
template <typename Scalar, typename Controller>
ControllerReport<Scalar> controller_report(
    const Controller& controller, Status status,
    Eigen::Matrix<Scalar, 1, kMaxLoggedParameters>& parameters) noexcept {
  ControllerReport<Scalar> report;
  report.status = status;
  report.s = controller.tracking().s;
  report.adaptive_norm = controller.adaptive_norm();
  constexpr int n = Controller::kLoggedParameters;
  static_assert(n <= kMaxLoggedParameters, "a controller logs more parameters than a row holds");
  report.parameter_count = n;
  if constexpr (n > 0) parameters.template head<n>() = controller.logged_parameters().transpose();
  report.parameters = parameters.data();
  return report;
}

namespace detail {

/// Steps `controller` and `sim` until the run is over or the log is full.
template <typename Scalar, typename Controller>
void run_until_log_full(Simulator<Scalar>& sim, Controller& controller,
                        Eigen::Matrix<Scalar, 1, kMaxLoggedParameters>& parameters) noexcept {
  Vector6<Scalar> tau;
  while (!sim.done() && !sim.log_full()) {
    const Observation<Scalar>& o = sim.observation();
    const Status cs = controller.step(o.eta, o.nu, o.desired, tau);
    sim.step(tau, controller_report<Scalar>(controller, cs, parameters));
  }
}

}  // namespace detail

/// Runs the closed loop. The controller is used as given (reset it first for
/// a fresh run) and left in its final state. Throws nothing; a bad
/// configuration comes back as the ValidationError with `out` untouched.
template <typename Scalar, typename Controller>
ValidationError simulate(const Vehicle<Scalar>& vehicle, Controller& controller,
                         const SimulationConfig<Scalar>& config, SimulationResult<Scalar>& out) {
  Eigen::Matrix<Scalar, 1, kMaxLoggedParameters> parameters;
  // The report fixes how many parameters the run logs.
  const int logged = controller_report<Scalar>(controller, Status::ok, parameters).parameter_count;
  Simulator<Scalar> sim;
  if (auto e = Simulator<Scalar>::create(vehicle, config, sim, logged)) return e;
  detail::run_until_log_full(sim, controller, parameters);
  sim.release_result(out);
  return {};
}

/// The same run with its rows handed over in chunks of at most `chunk_rows`
/// rows, in time order: `sink(const SimulationResult<Scalar>&)` gets each
/// (the last may be shorter; its `diverged` says how the run ended), so a run
/// of any length holds one chunk in memory. The chunks together are the rows
/// simulate() returns. A bad configuration or `chunk_rows` < 1 comes back as
/// the ValidationError before any step; what `sink` throws ends the run.
template <typename Scalar, typename Controller, typename Sink>
ValidationError simulate_in_chunks(const Vehicle<Scalar>& vehicle, Controller& controller,
                                   const SimulationConfig<Scalar>& config,
                                   Eigen::Index chunk_rows, Sink&& sink) {
  if (chunk_rows < 1)
    return detail::invalid("chunk_rows", -1, static_cast<double>(chunk_rows), ">= 1");
  Eigen::Matrix<Scalar, 1, kMaxLoggedParameters> parameters;
  const int logged = controller_report<Scalar>(controller, Status::ok, parameters).parameter_count;
  Simulator<Scalar> sim;
  if (auto e = Simulator<Scalar>::create(vehicle, config, sim, logged, chunk_rows)) return e;
  SimulationResult<Scalar> chunk;
  do {
    detail::run_until_log_full(sim, controller, parameters);
    sim.drain(chunk);
    sink(static_cast<const SimulationResult<Scalar>&>(chunk));
  } while (!sim.done());
  return {};
}

}  // namespace neurov
