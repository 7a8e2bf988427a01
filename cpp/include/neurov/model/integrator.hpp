// Fixed-step fourth-order Runge-Kutta for the 12-state plant x = (eta, nu)
// under a force tau held constant over the step (zero-order hold). Only the
// vehicle's scalar type is deduced, so tau and dt may be any expression.
#pragma once

#include <cmath>

#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/model/vehicle.hpp"

namespace neurov {

/// Advances (eta, nu) by dt in place. On invalid_argument (dt <= 0 or not
/// finite, empty vehicle), non_finite_input or non_finite_output the state is
/// left exactly as it was. near_singularity means a stage ran with a clamped
/// cos(theta) (pitch at +-90 deg); the finite result is kept and flagged.
template <typename Scalar>
inline Status rk4_step(const Vehicle<Scalar>& vehicle, Vector6<Scalar>& eta, Vector6<Scalar>& nu,
                       const typename Vehicle<Scalar>::Vec6& tau,
                       typename Vehicle<Scalar>::Scalar dt,
                       const typename Vehicle<Scalar>::Vec3& current_ned =
                           Vector3<Scalar>::Zero()) noexcept {
  if (detail::check_step("dt", static_cast<double>(dt))) return Status::invalid_argument;
  using V6 = Vector6<Scalar>;
  V6 k1e, k1n, k2e, k2n, k3e, k3n, k4e, k4n;
  const Scalar h2 = Scalar(0.5) * dt;
  Status s = vehicle.derivative(eta, nu, tau, current_ned, k1e, k1n);
  if (s != Status::ok && s != Status::near_singularity) return s;
  Status flag = s;
  s = vehicle.derivative(eta + h2 * k1e, nu + h2 * k1n, tau, current_ned, k2e, k2n);
  if (s != Status::ok && s != Status::near_singularity) return Status::non_finite_output;
  flag = worst(flag, s);
  s = vehicle.derivative(eta + h2 * k2e, nu + h2 * k2n, tau, current_ned, k3e, k3n);
  if (s != Status::ok && s != Status::near_singularity) return Status::non_finite_output;
  flag = worst(flag, s);
  s = vehicle.derivative(eta + dt * k3e, nu + dt * k3n, tau, current_ned, k4e, k4n);
  if (s != Status::ok && s != Status::near_singularity) return Status::non_finite_output;
  flag = worst(flag, s);
  const Scalar h6 = dt / Scalar(6);
  const V6 eta_next = eta + h6 * (k1e + Scalar(2) * (k2e + k3e) + k4e);
  const V6 nu_next = nu + h6 * (k1n + Scalar(2) * (k2n + k3n) + k4n);
  if (!detail::all_finite(eta_next, nu_next)) return Status::non_finite_output;
  eta = eta_next;
  nu = nu_next;
  return flag;
}

}  // namespace neurov
