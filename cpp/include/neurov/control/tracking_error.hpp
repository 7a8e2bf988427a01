// Tracking error and virtual reference (eq. 11, 14-16), shared by every
// controller and computed once per step:
//   eta_tilde = eta - eta_d,  s = eta_tilde_dot + Lambda eta_tilde
//   eta_r_dot = eta_d_dot - Lambda eta_tilde,  eta_r_ddot = eta_d_ddot - Lambda eta_tilde_dot
//   nu_r = J^-1(eta) eta_r_dot,  nu_r_dot = J^-1(eta) (eta_r_ddot - J_dot(eta, nu) nu_r)
#pragma once

#include "neurov/model/kinematics.hpp"
#include "neurov/model/regressor.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"

namespace neurov {

template <typename Scalar>
struct TrackingError {
  Vector6<Scalar> eta_tilde = Vector6<Scalar>::Zero();
  Vector6<Scalar> eta_tilde_dot = Vector6<Scalar>::Zero();
  Vector6<Scalar> s = Vector6<Scalar>::Zero();  ///< filtered tracking error
  Vector6<Scalar> eta_r_dot = Vector6<Scalar>::Zero();
  Vector6<Scalar> eta_r_ddot = Vector6<Scalar>::Zero();
  Vector6<Scalar> nu_r = Vector6<Scalar>::Zero();
  Vector6<Scalar> nu_r_dot = Vector6<Scalar>::Zero();
  /// J(eta) of the vehicle's pose, for the controllers' J^T K_d s and J^-1 s.
  EulerKinematics<Scalar> kinematics = EulerKinematics<Scalar>::from_pose(Vector6<Scalar>::Zero());
};

/// Fills `out` from the measured (eta, nu), the desired trajectory and the
/// diagonal Lambda. Returns non_finite_input if any input is NaN/Inf and
/// near_singularity at pitch +-90 deg; `out` is then unchanged.
template <typename Scalar>
inline Status compute_tracking_error(const Vector6<Scalar>& eta, const Vector6<Scalar>& nu,
                                     const Vector6<Scalar>& eta_d, const Vector6<Scalar>& eta_d_dot,
                                     const Vector6<Scalar>& eta_d_ddot,
                                     const Vector6<Scalar>& lambda,
                                     TrackingError<Scalar>& out) noexcept {
  if (!detail::all_finite(eta, nu, eta_d, eta_d_dot, eta_d_ddot)) return Status::non_finite_input;
  const auto k = EulerKinematics<Scalar>::from_pose(eta);
  if (k.status() != Status::ok) return k.status();
  // Locals, written to `out` only once they are known to be finite (no
  // second TrackingError to build and copy).
  const Vector6<Scalar> eta_tilde = eta - eta_d;
  const Vector6<Scalar> eta_tilde_dot = k.apply(nu) - eta_d_dot;
  const Vector6<Scalar> s = eta_tilde_dot + lambda.cwiseProduct(eta_tilde);
  const Vector6<Scalar> eta_r_dot = eta_d_dot - lambda.cwiseProduct(eta_tilde);
  const Vector6<Scalar> eta_r_ddot = eta_d_ddot - lambda.cwiseProduct(eta_tilde_dot);
  const Vector6<Scalar> nu_r = k.apply_inverse(eta_r_dot);
  const Vector6<Scalar> nu_r_dot = k.apply_inverse(eta_r_ddot - k.apply_dot(nu, nu_r));
  if (!detail::all_finite(s, nu_r, nu_r_dot)) return Status::non_finite_output;
  out.kinematics = k;
  out.eta_tilde = eta_tilde;
  out.eta_tilde_dot = eta_tilde_dot;
  out.s = s;
  out.eta_r_dot = eta_r_dot;
  out.eta_r_ddot = eta_r_ddot;
  out.nu_r = nu_r;
  out.nu_r_dot = nu_r_dot;
  return Status::ok;
}

/// Phi at the virtual reference: Phi(nu_r_dot, nu_r, nu) at the measured
/// attitude, so that Phi theta is the model's force along the reference (the
/// laws on f = Phi theta: linear adaptive, sliding mode, super-twisting).
template <typename Scalar>
inline RegressorMatrix<Scalar> reference_regressor(const TrackingError<Scalar>& e,
                                                   const Vector6<Scalar>& nu) noexcept {
  const auto& trig = e.kinematics.trig;
  return regressor<Scalar>(e.nu_r_dot, e.nu_r, nu, trig.sin_phi, trig.cos_phi, trig.sin_theta,
                           trig.cos_theta);
}

}  // namespace neurov
