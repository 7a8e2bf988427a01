// Closed-loop simulation: plant, reference model, controller, thrusters,
// disturbances and measurement noise, all in C++ so a whole run is one call.
//
// Timing: control at dt (the paper's 5 Hz by default) with the thrust held
// over each control interval (zero-order hold); the plant integrated by RK4 at
// dt / substeps; the reference model advanced at the control rate. Row k of
// the result is the instant t_k = k dt: the true state there, the desired
// state the controller was given, and the force it demanded for [t_k, t_k+1).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "neurov/control/desired_state.hpp"
#include "neurov/model/integrator.hpp"
#include "neurov/control/linear_adaptive_controller.hpp"
#include "neurov/control/nn_controller.hpp"
#include "neurov/control/pd_controller.hpp"
#include "neurov/control/pid_controller.hpp"
#include "neurov/core/random.hpp"
#include "neurov/control/reference_model.hpp"
#include "neurov/control/sliding_mode_controller.hpp"
#include "neurov/core/status.hpp"
#include "neurov/model/thrusters.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/vehicle.hpp"

namespace neurov {

/// A sinusoidal force or moment in one body DOF:
/// amplitude * sin(2 pi frequency (t - start) + phase) for t >= start.
template <typename Scalar>
struct SinusoidalDisturbance {
  int dof = 5;  ///< 0..5: surge, sway, heave, roll, pitch, yaw
  Scalar amplitude = Scalar(0);  ///< [N] or [N m]
  Scalar frequency = Scalar(0);  ///< [Hz]
  Scalar phase = Scalar(0);      ///< [rad]
  Scalar start = Scalar(0);      ///< [s]
};

/// Thruster i works at `efficiency` (0: failed) from `time` on.
template <typename Scalar>
struct ThrusterFailure {
  int index = 0;
  Scalar efficiency = Scalar(0);
  Scalar time = Scalar(0);
};

/// A sensor fault over [start, end): the measurement of eta and/or nu freezes
/// at its last value, drops out (NaN, which the controller refuses), or gets
/// extra white noise of the given standard deviations.
enum class SensorFaultKind : std::uint8_t { freeze = 0, dropout = 1, noise_burst = 2 };

template <typename Scalar>
struct SensorFault {
  SensorFaultKind kind = SensorFaultKind::freeze;
  Scalar start = Scalar(0);
  Scalar end = Scalar(0);
  bool eta = true;  ///< affects the pose measurement
  bool nu = true;   ///< affects the velocity measurement
  Vector6<Scalar> noise_eta = Vector6<Scalar>::Zero();  ///< noise_burst only
  Vector6<Scalar> noise_nu = Vector6<Scalar>::Zero();   ///< noise_burst only
};

/// From `time` on, the mean current is `velocity` (NED): a step in the current.
template <typename Scalar>
struct CurrentStep {
  Scalar time = Scalar(0);
  Vector3<Scalar> velocity = Vector3<Scalar>::Zero();
};

/// What the loop applies when the controller refuses a step (a NaN
/// measurement, the pitch singularity): the zero force the controller writes,
/// or the last force it accepted.
enum class RefusedStepPolicy : std::uint8_t { zero = 0, hold = 1 };

/// Bits of SimulationResult::faults, one per kind of fault active in a step.
namespace fault_bits {
constexpr std::uint8_t freeze = 1;
constexpr std::uint8_t dropout = 2;
constexpr std::uint8_t noise_burst = 4;
constexpr std::uint8_t thruster = 8;  ///< some thruster below full efficiency
/// The row's desired state came from a reference step that limited the pitch
/// (ReferenceModel::pitch_limited(): the command's pitch clamped, or the
/// reference's own held at the limit).
constexpr std::uint8_t pitch_limited = 16;
}  // namespace fault_bits

/// Commanded poses r(t) at increasing times; held before the first and after
/// the last; between them linear or held (piecewise constant).
template <typename Scalar>
struct Command {
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> times;
  Eigen::Matrix<Scalar, Eigen::Dynamic, 6, Eigen::RowMajor> poses;
  bool linear = true;

  Vector6<Scalar> at(Scalar t) const noexcept {
    const Eigen::Index n = times.size();
    if (n == 0) return Vector6<Scalar>::Zero();
    if (t <= times(0)) return poses.row(0).transpose();
    if (t >= times(n - 1)) return poses.row(n - 1).transpose();
    Eigen::Index lo = 0, hi = n - 1;  // binary search: times(lo) <= t < times(hi)
    while (hi - lo > 1) {
      const Eigen::Index mid = (lo + hi) / 2;
      (times(mid) <= t ? lo : hi) = mid;
    }
    if (!linear) return poses.row(lo).transpose();
    const Scalar a = (t - times(lo)) / (times(hi) - times(lo));
    return ((Scalar(1) - a) * poses.row(lo) + a * poses.row(hi)).transpose();
  }
};

template <typename Scalar>
struct SimulationConfig {
  Scalar dt = Scalar(0.2);  ///< control period [s]
  int substeps = 10;        ///< RK4 steps per control period
  Scalar duration = Scalar(60);
  Vector6<Scalar> eta0 = Vector6<Scalar>::Zero();
  Vector6<Scalar> nu0 = Vector6<Scalar>::Zero();
  Command<Scalar> command;
  Vector6<Scalar> lambda_d = Vector6<Scalar>::Constant(Scalar(1));  ///< reference damping
  Vector6<Scalar> omega = Vector6<Scalar>::Constant(Scalar(0.25));  ///< reference stiffness
  std::vector<SinusoidalDisturbance<Scalar>> disturbances;
  /// Current in NED: mean + amplitude * sin(2 pi t / period) per axis.
  Vector3<Scalar> current = Vector3<Scalar>::Zero();
  Vector3<Scalar> current_amplitude = Vector3<Scalar>::Zero();
  Scalar current_period = Scalar(0);  ///< [s]; 0 means a constant current
  /// Standard deviations of white Gaussian noise on the measured eta and nu.
  Vector6<Scalar> noise_eta = Vector6<Scalar>::Zero();
  Vector6<Scalar> noise_nu = Vector6<Scalar>::Zero();
  std::uint64_t seed = 0;
  bool use_thrusters = false;
  ThrusterConfig<Scalar> thrusters;
  std::vector<ThrusterFailure<Scalar>> failures;
  std::vector<SensorFault<Scalar>> sensor_faults;
  std::vector<CurrentStep<Scalar>> current_steps;  ///< in increasing time
  RefusedStepPolicy refused_step_policy = RefusedStepPolicy::zero;
};

template <typename Scalar>
struct SimulationResult {
  using Rows6 = Eigen::Matrix<Scalar, Eigen::Dynamic, 6, Eigen::RowMajor>;
  using RowsX = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> t;
  Rows6 eta, nu, eta_d, eta_d_dot, tau_demanded, tau_applied, disturbance, s;
  RowsX thrusts;      ///< produced thrust per thruster (mean over the interval)
  RowsX theta;        ///< theta_hat per step (linear adaptive controller only)
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> adaptive_norm;  ///< ||W||_F or ||theta_hat||
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1> controller_status;
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1> plant_status;
  /// fault_bits active in each step.
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1> faults;
  /// Rows actually simulated: fewer than planned if the plant diverged.
  Eigen::Index steps = 0;
  bool diverged = false;
};

template <typename Scalar>
inline ValidationError validate(const SimulationConfig<Scalar>& c) {
  if (auto e = detail::check_step("dt", static_cast<double>(c.dt))) return e;
  if (c.substeps < 1)
    return detail::invalid("substeps", -1, static_cast<double>(c.substeps), ">= 1");
  if (auto e = detail::check_positive_scalar("duration", static_cast<double>(c.duration))) return e;
  if (c.duration / c.dt > Scalar(1e8))
    return detail::invalid("duration", -1, static_cast<double>(c.duration),
                           "at most 1e8 control steps");
  if (auto e = detail::check_finite("eta0", c.eta0)) return e;
  if (auto e = detail::check_finite("nu0", c.nu0)) return e;
  if (c.command.times.size() < 1)
    return detail::invalid("command.times", -1, 0.0, "at least one commanded pose");
  if (c.command.poses.rows() != c.command.times.size())
    return detail::invalid("command.poses", -1, static_cast<double>(c.command.poses.rows()),
                           "one pose per time");
  if (auto e = detail::check_finite("command.times", c.command.times)) return e;
  if (auto e = detail::check_finite("command.poses", c.command.poses)) return e;
  for (Eigen::Index i = 1; i < c.command.times.size(); ++i)
    if (!(c.command.times(i) > c.command.times(i - 1)))
      return detail::invalid("command.times", static_cast<int>(i),
                             static_cast<double>(c.command.times(i)), "strictly increasing");
  if (auto e = detail::check_positive("lambda_d", c.lambda_d)) return e;
  if (auto e = detail::check_positive("omega", c.omega)) return e;
  for (std::size_t i = 0; i < c.disturbances.size(); ++i) {
    const auto& d = c.disturbances[i];
    if (d.dof < 0 || d.dof > 5)
      return detail::invalid("disturbances.dof", static_cast<int>(i), d.dof, "0..5");
    if (!(std::isfinite(d.amplitude) && std::isfinite(d.phase) && std::isfinite(d.start)))
      return detail::invalid("disturbances", static_cast<int>(i), std::nan(""),
                             "finite amplitude, phase and start");
    if (!(std::isfinite(d.frequency) && d.frequency >= Scalar(0)))
      return detail::invalid("disturbances.frequency", static_cast<int>(i),
                             static_cast<double>(d.frequency), ">= 0 and finite");
  }
  if (auto e = detail::check_finite("current", c.current)) return e;
  if (auto e = detail::check_finite("current_amplitude", c.current_amplitude)) return e;
  if (auto e = detail::check_non_negative_scalar("current_period",
                                                 static_cast<double>(c.current_period)))
    return e;
  if (auto e = detail::check_non_negative("noise_eta", c.noise_eta)) return e;
  if (auto e = detail::check_non_negative("noise_nu", c.noise_nu)) return e;
  for (std::size_t i = 0; i < c.failures.size(); ++i) {
    const auto& f = c.failures[i];
    if (!c.use_thrusters)
      return detail::invalid("thruster_failures", static_cast<int>(i), std::nan(""),
                             "a thruster configuration");
    if (f.index < 0 || f.index >= c.thrusters.matrix.cols())
      return detail::invalid("thruster_failures.index", static_cast<int>(i), f.index,
                             "a thruster index");
    if (!(f.efficiency >= Scalar(0) && f.efficiency <= Scalar(1)))
      return detail::invalid("thruster_failures.efficiency", static_cast<int>(i),
                             static_cast<double>(f.efficiency), "in [0, 1]");
    if (!std::isfinite(f.time))
      return detail::invalid("thruster_failures.time", static_cast<int>(i),
                             static_cast<double>(f.time), "finite");
  }
  for (std::size_t i = 0; i < c.sensor_faults.size(); ++i) {
    const auto& f = c.sensor_faults[i];
    if (!(std::isfinite(f.start) && std::isfinite(f.end) && f.end >= f.start))
      return detail::invalid("sensor_faults", static_cast<int>(i), static_cast<double>(f.end),
                             "finite start <= end");
    if (static_cast<int>(f.kind) > 2)
      return detail::invalid("sensor_faults.kind", static_cast<int>(i),
                             static_cast<double>(f.kind), "freeze, dropout or noise_burst");
    if (auto e = detail::check_non_negative("sensor_faults.noise_eta", f.noise_eta)) return e;
    if (auto e = detail::check_non_negative("sensor_faults.noise_nu", f.noise_nu)) return e;
  }
  for (std::size_t i = 0; i < c.current_steps.size(); ++i) {
    if (!std::isfinite(c.current_steps[i].time) ||
        (i > 0 && !(c.current_steps[i].time > c.current_steps[i - 1].time)))
      return detail::invalid("current_steps.time", static_cast<int>(i),
                             static_cast<double>(c.current_steps[i].time),
                             "finite and strictly increasing");
    if (auto e = detail::check_finite("current_steps.velocity", c.current_steps[i].velocity))
      return e;
  }
  return {};
}

/// Runs the closed loop. The controller is used as given (reset it first for
/// a fresh run) and left in its final state. Throws nothing; a bad
/// configuration comes back as the ValidationError and an empty result.
template <typename Scalar, typename Controller>
ValidationError simulate(const Vehicle<Scalar>& vehicle, Controller& controller,
                         const SimulationConfig<Scalar>& config, SimulationResult<Scalar>& out) {
  using Vec3 = Vector3<Scalar>;
  using Vec6 = Vector6<Scalar>;
  if (!vehicle.valid()) return detail::invalid("vehicle", -1, std::nan(""), "a valid vehicle");
  if (auto e = validate(config)) return e;
  ReferenceModel<Scalar> reference;
  if (auto e = ReferenceModel<Scalar>::create(config.lambda_d, config.omega, config.eta0, reference))
    return e;
  Thrusters<Scalar> thrusters;
  if (config.use_thrusters)
    if (auto e = Thrusters<Scalar>::create(config.thrusters, thrusters)) return e;

  const Eigen::Index rows = static_cast<Eigen::Index>(std::llround(config.duration / config.dt)) + 1;
  const Eigen::Index n_thr = config.use_thrusters ? thrusters.count() : 0;
  constexpr int n_theta = Controller::kLoggedParameters;
  SimulationResult<Scalar>& r = out;
  r.t.resize(rows);
  for (auto* m : {&r.eta, &r.nu, &r.eta_d, &r.eta_d_dot, &r.tau_demanded, &r.tau_applied,
                  &r.disturbance, &r.s})
    m->setZero(rows, 6);
  r.thrusts.setZero(rows, n_thr);
  r.theta.setZero(rows, n_theta);
  r.adaptive_norm.setZero(rows);
  r.controller_status.setZero(rows);
  r.plant_status.setZero(rows);
  r.faults.setZero(rows);
  r.diverged = false;

  NormalRandom rng(config.seed);
  const bool noisy = !(config.noise_eta.isZero(Scalar(0)) && config.noise_nu.isZero(Scalar(0)));
  const Scalar h = config.dt / static_cast<Scalar>(config.substeps);
  const Scalar two_pi = Scalar(6.283185307179586);
  std::vector<bool> failure_applied(config.failures.size(), false);

  auto disturbance_at = [&](Scalar t) {
    Vec6 d = Vec6::Zero();
    for (const auto& s : config.disturbances)
      if (t >= s.start)
        d(s.dof) += s.amplitude * std::sin(two_pi * s.frequency * (t - s.start) + s.phase);
    return d;
  };
  auto current_at = [&](Scalar t) {
    Vec3 c = config.current;
    for (const auto& step : config.current_steps)
      if (t >= step.time) c = step.velocity;
    if (config.current_period > Scalar(0))
      c += config.current_amplitude * std::sin(two_pi * t / config.current_period);
    return c;
  };

  Vec6 eta = config.eta0, nu = config.nu0;
  DesiredState<Scalar> desired = reference.desired();
  // The last measurements delivered unfrozen, which a freeze keeps repeating.
  Vec6 held_eta = eta, held_nu = nu;
  Vec6 last_accepted_tau = Vec6::Zero();
  const Scalar nan = std::numeric_limits<Scalar>::quiet_NaN();
  Eigen::Index k = 0;
  for (; k < rows; ++k) {
    const Scalar t = static_cast<Scalar>(k) * config.dt;
    Vec6 eta_m = eta, nu_m = nu;
    if (noisy) {
      for (int i = 0; i < 6; ++i) {
        eta_m(i) += config.noise_eta(i) * static_cast<Scalar>(rng.normal());
        nu_m(i) += config.noise_nu(i) * static_cast<Scalar>(rng.normal());
      }
    }
    // `desired` (this row's eta_d) is from the last accepted reference step.
    std::uint8_t faults = reference.pitch_limited() ? fault_bits::pitch_limited : std::uint8_t(0);
    bool freeze_eta = false, freeze_nu = false;
    for (const auto& f : config.sensor_faults) {
      if (!(t >= f.start && t < f.end)) continue;
      if (f.kind == SensorFaultKind::freeze) {
        faults |= fault_bits::freeze;
        freeze_eta = freeze_eta || f.eta;
        freeze_nu = freeze_nu || f.nu;
      } else if (f.kind == SensorFaultKind::dropout) {
        faults |= fault_bits::dropout;
        if (f.eta) eta_m.setConstant(nan);
        if (f.nu) nu_m.setConstant(nan);
      } else {
        faults |= fault_bits::noise_burst;
        for (int i = 0; i < 6; ++i) {
          if (f.eta) eta_m(i) += f.noise_eta(i) * static_cast<Scalar>(rng.normal());
          if (f.nu) nu_m(i) += f.noise_nu(i) * static_cast<Scalar>(rng.normal());
        }
      }
    }
    if (freeze_eta)
      eta_m = held_eta;
    else if (eta_m.allFinite())
      held_eta = eta_m;
    if (freeze_nu)
      nu_m = held_nu;
    else if (nu_m.allFinite())
      held_nu = nu_m;
    Vec6 tau;
    const Status cs = controller.step(eta_m, nu_m, desired, tau);
    if (cs == Status::ok)
      last_accepted_tau = tau;
    else if (config.refused_step_policy == RefusedStepPolicy::hold)
      tau = last_accepted_tau;

    r.t(k) = t;
    r.eta.row(k) = eta.transpose();
    r.nu.row(k) = nu.transpose();
    r.eta_d.row(k) = desired.eta_d.transpose();
    r.eta_d_dot.row(k) = desired.eta_d_dot.transpose();
    r.tau_demanded.row(k) = tau.transpose();
    r.s.row(k) = controller.tracking().s.transpose();
    r.adaptive_norm(k) = controller.adaptive_norm();
    r.controller_status(k) = static_cast<std::uint8_t>(cs);
    if constexpr (n_theta > 0) r.theta.row(k) = controller.logged_parameters().transpose();
    r.disturbance.row(k) = disturbance_at(t).transpose();

    if (config.use_thrusters) thrusters.command(tau);
    Status ps = Status::ok;
    Vec6 applied_sum = Vec6::Zero();
    for (int j = 0; j < config.substeps; ++j) {
      const Scalar ts = t + static_cast<Scalar>(j) * h;
      Vec6 applied = tau;
      if (config.use_thrusters) {
        for (std::size_t f = 0; f < config.failures.size(); ++f) {
          if (!failure_applied[f] && ts >= config.failures[f].time) {
            thrusters.set_efficiency(config.failures[f].index, config.failures[f].efficiency);
            failure_applied[f] = true;
          }
        }
        // Checked per substep, where a failure or repair takes effect, so the
        // bit describes the same interval as this row's thrusts and tau_applied.
        if ((thrusters.efficiency().array() < Scalar(1)).any()) faults |= fault_bits::thruster;
        thrusters.advance(h);
        applied = thrusters.wrench();
        if (n_thr > 0)
          r.thrusts.row(k) +=
              thrusters.efficiency().cwiseProduct(thrusters.thrust()).transpose() /
              static_cast<Scalar>(config.substeps);
      }
      applied_sum += applied;
      ps = worst(ps, rk4_step(vehicle, eta, nu, (applied + disturbance_at(ts)).eval(), h,
                              current_at(ts)));
      if (ps != Status::ok && ps != Status::near_singularity) break;
    }
    r.tau_applied.row(k) = (applied_sum / static_cast<Scalar>(config.substeps)).transpose();
    r.plant_status(k) = static_cast<std::uint8_t>(ps);
    r.faults(k) = faults;
    if (ps != Status::ok && ps != Status::near_singularity) {
      r.diverged = true;
      ++k;
      break;
    }
    // The desired state for t_{k+1}; on a refused step it stays where it was.
    reference.step(config.command.at(t), config.dt, desired);
  }
  r.steps = k;
  if (k < rows) {
    // Keep only the rows simulated before the plant diverged.
    r.t.conservativeResize(k);
    for (auto* m : {&r.eta, &r.nu, &r.eta_d, &r.eta_d_dot, &r.tau_demanded, &r.tau_applied,
                    &r.disturbance, &r.s})
      m->conservativeResize(k, 6);
    r.thrusts.conservativeResize(k, n_thr);
    r.theta.conservativeResize(k, n_theta);
    r.adaptive_norm.conservativeResize(k);
    r.controller_status.conservativeResize(k);
    r.plant_status.conservativeResize(k);
    r.faults.conservativeResize(k);
  }
  return {};
}

}  // namespace neurov
