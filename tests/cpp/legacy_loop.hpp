// TEMPORARY: the closed loop as it was before the Simulator (verbatim but for
// its name), to show that the Simulator gives the same runs to the bit.
#pragma once

#include "neurov/neurov.hpp"

namespace neurov::legacy {

template <typename Scalar, typename Controller>
ValidationError simulate_legacy(const Vehicle<Scalar>& vehicle, Controller& controller,
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
  const int n_theta = detail::theta_columns(&controller);
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
    r.adaptive_norm(k) = adaptive_norm(controller);
    r.controller_status(k) = static_cast<std::uint8_t>(cs);
    detail::record_theta(controller, r.theta.row(k));
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

}  // namespace neurov::legacy
