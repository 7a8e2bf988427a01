// Euler-angle (ZYX) kinematics of a 6-DOF vehicle, eq. 2 of the paper:
//   eta_dot = J(eta) nu,  J = blockdiag(R(phi, theta, psi), T(phi, theta)).
// Everything is closed form: J^-1 = blockdiag(R^T, T^-1) and J_dot from
// R_dot = R S(omega) and T_dot = dT/dphi phi_dot + dT/dtheta theta_dot.
//
// T and J_dot divide by cos(theta). Below the singularity threshold the
// functions clamp cos(theta) to +-threshold (keeping its sign), so every output
// stays finite, and they return Status::near_singularity so the caller knows
// the numbers are not to be trusted.
#pragma once

#include <cmath>
#include <limits>

#include "neurov/core/status.hpp"
#include "neurov/core/trig.hpp"
#include "neurov/core/types.hpp"

namespace neurov {

/// |cos(theta)| below which the Euler transform counts as singular. At
/// sqrt(epsilon) the rounding error of cos(theta) near +-90 deg (about epsilon)
/// is already a sqrt(epsilon) relative error in 1/cos(theta).
template <typename Scalar>
inline Scalar singularity_threshold() noexcept {
  return std::sqrt(std::numeric_limits<Scalar>::epsilon());
}

/// Sines and cosines of the Euler angles, computed once and shared by every
/// kinematic quantity of one step. `cos_theta` is the true cosine (R, T^-1
/// and g need no division and stay exact at the singularity); `sec_theta` is
/// 1 / cos(theta) with cos(theta) clamped away from 0, for T and T_dot.
template <typename Scalar>
struct EulerTrig {
  Scalar sin_phi, cos_phi, sin_theta, cos_theta, sin_psi, cos_psi, sec_theta;
  Status status = Status::ok;

  static EulerTrig from_angles(Scalar phi, Scalar theta, Scalar psi) noexcept {
    EulerTrig t;
    if (!(std::isfinite(phi) && std::isfinite(theta) && std::isfinite(psi))) {
      // Identity attitude: finite, and the status tells the caller why.
      t.sin_phi = t.sin_theta = t.sin_psi = Scalar(0);
      t.cos_phi = t.cos_theta = t.cos_psi = t.sec_theta = Scalar(1);
      t.status = Status::non_finite_input;
      return t;
    }
    detail::sincos(phi, t.sin_phi, t.cos_phi);
    detail::sincos(theta, t.sin_theta, t.cos_theta);
    detail::sincos(psi, t.sin_psi, t.cos_psi);
    const Scalar threshold = singularity_threshold<Scalar>();
    if (std::abs(t.cos_theta) < threshold) {
      t.sec_theta = Scalar(1) / std::copysign(threshold, t.cos_theta);
      t.status = Status::near_singularity;
    } else {
      t.sec_theta = Scalar(1) / t.cos_theta;
    }
    return t;
  }

  static EulerTrig from_pose(const Vector6<Scalar>& eta) noexcept {
    return from_angles(eta(3), eta(4), eta(5));
  }
};

/// R(phi, theta, psi) = Rz(psi) Ry(theta) Rx(phi): body to earth (NED).
template <typename Scalar>
inline Matrix3<Scalar> rotation(const EulerTrig<Scalar>& t) noexcept {
  const Scalar cf = t.cos_phi, sf = t.sin_phi, ct = t.cos_theta, st = t.sin_theta;
  const Scalar cp = t.cos_psi, sp = t.sin_psi;
  Matrix3<Scalar> r;
  r << cp * ct, -sp * cf + cp * st * sf, sp * sf + cp * cf * st,  //
      sp * ct, cp * cf + sf * st * sp, -cp * sf + st * sp * cf,   //
      -st, ct * sf, ct * cf;
  return r;
}

template <typename Scalar>
inline Matrix3<Scalar> rotation(Scalar phi, Scalar theta, Scalar psi) noexcept {
  return rotation(EulerTrig<Scalar>::from_angles(phi, theta, psi));
}

/// T(phi, theta): body angular rates to Euler-angle rates.
template <typename Scalar>
inline Matrix3<Scalar> attitude_transform(const EulerTrig<Scalar>& t) noexcept {
  const Scalar cf = t.cos_phi, sf = t.sin_phi, sec = t.sec_theta;
  const Scalar tt = t.sin_theta * sec;
  Matrix3<Scalar> m;
  m << Scalar(1), sf * tt, cf * tt,  //
      Scalar(0), cf, -sf,            //
      Scalar(0), sf * sec, cf * sec;
  return m;
}

/// T^-1(phi, theta): Euler-angle rates to body angular rates (no division).
template <typename Scalar>
inline Matrix3<Scalar> attitude_transform_inverse(const EulerTrig<Scalar>& t) noexcept {
  const Scalar cf = t.cos_phi, sf = t.sin_phi, ct = t.cos_theta, st = t.sin_theta;
  Matrix3<Scalar> m;
  m << Scalar(1), Scalar(0), -st,  //
      Scalar(0), cf, ct * sf,      //
      Scalar(0), -sf, ct * cf;
  return m;
}

/// T_dot(phi, theta, phi_dot, theta_dot) = dT/dphi * phi_dot + dT/dtheta * theta_dot.
template <typename Scalar>
inline Matrix3<Scalar> attitude_transform_dot(const EulerTrig<Scalar>& t, Scalar phi_dot,
                                              Scalar theta_dot) noexcept {
  const Scalar cf = t.cos_phi, sf = t.sin_phi, sec = t.sec_theta;
  const Scalar tt = t.sin_theta * sec;
  const Scalar sec2 = sec * sec;
  Matrix3<Scalar> m;
  m << Scalar(0), cf * tt * phi_dot + sf * sec2 * theta_dot,
      -sf * tt * phi_dot + cf * sec2 * theta_dot,  //
      Scalar(0), -sf * phi_dot, -cf * phi_dot,     //
      Scalar(0), (cf * phi_dot + sf * tt * theta_dot) * sec,
      (-sf * phi_dot + cf * tt * theta_dot) * sec;
  return m;
}

/// The Jacobian J(eta) of one pose, held as its two 3x3 blocks so that products
/// with J, J^-1 and J^T cost two 3x3 products rather than a 6x6 one.
template <typename Scalar>
struct EulerKinematics {
  EulerTrig<Scalar> trig;
  Matrix3<Scalar> R;      // rotation, body -> earth
  Matrix3<Scalar> T;      // attitude transform
  Matrix3<Scalar> T_inv;  // its closed-form inverse

  Status status() const noexcept { return trig.status; }

  static EulerKinematics from_pose(const Vector6<Scalar>& eta) noexcept {
    EulerKinematics k;
    k.trig = EulerTrig<Scalar>::from_pose(eta);
    k.R = rotation(k.trig);
    k.T = attitude_transform(k.trig);
    k.T_inv = attitude_transform_inverse(k.trig);
    return k;
  }

  /// J nu.
  Vector6<Scalar> apply(const Vector6<Scalar>& v) const noexcept {
    Vector6<Scalar> out;
    out.template head<3>().noalias() = R * v.template head<3>();
    out.template tail<3>().noalias() = T * v.template tail<3>();
    return out;
  }
  /// J^-1 v.
  Vector6<Scalar> apply_inverse(const Vector6<Scalar>& v) const noexcept {
    Vector6<Scalar> out;
    out.template head<3>().noalias() = R.transpose() * v.template head<3>();
    out.template tail<3>().noalias() = T_inv * v.template tail<3>();
    return out;
  }
  /// J^T v.
  Vector6<Scalar> apply_transpose(const Vector6<Scalar>& v) const noexcept {
    Vector6<Scalar> out;
    out.template head<3>().noalias() = R.transpose() * v.template head<3>();
    out.template tail<3>().noalias() = T.transpose() * v.template tail<3>();
    return out;
  }
  /// J_dot(eta, nu) v, with nu the body velocity that moves the pose.
  Vector6<Scalar> apply_dot(const Vector6<Scalar>& nu, const Vector6<Scalar>& v) const noexcept {
    const Vector3<Scalar> omega = nu.template tail<3>();
    const Vector3<Scalar> euler_rate = T * omega;
    Vector6<Scalar> out;
    // R_dot v = R (omega x v).
    out.template head<3>().noalias() = R * omega.cross(Vector3<Scalar>(v.template head<3>()));
    out.template tail<3>().noalias() =
        attitude_transform_dot(trig, euler_rate(0), euler_rate(1)) * v.template tail<3>();
    return out;
  }

  Matrix6<Scalar> jacobian() const noexcept {
    Matrix6<Scalar> j = Matrix6<Scalar>::Zero();
    j.template topLeftCorner<3, 3>() = R;
    j.template bottomRightCorner<3, 3>() = T;
    return j;
  }
  Matrix6<Scalar> jacobian_inverse() const noexcept {
    Matrix6<Scalar> j = Matrix6<Scalar>::Zero();
    j.template topLeftCorner<3, 3>() = R.transpose();
    j.template bottomRightCorner<3, 3>() = T_inv;
    return j;
  }
  Matrix6<Scalar> jacobian_dot(const Vector6<Scalar>& nu) const noexcept {
    const Vector3<Scalar> omega = nu.template tail<3>();
    const Vector3<Scalar> euler_rate = T * omega;
    Matrix6<Scalar> j = Matrix6<Scalar>::Zero();
    j.template topLeftCorner<3, 3>().noalias() = R * skew(omega);
    j.template bottomRightCorner<3, 3>() =
        attitude_transform_dot(trig, euler_rate(0), euler_rate(1));
    return j;
  }
};

/// J(eta). Returns near_singularity or non_finite_input (outputs stay finite).
template <typename Scalar>
inline Status jacobian(const Vector6<Scalar>& eta, Matrix6<Scalar>& out) noexcept {
  const auto k = EulerKinematics<Scalar>::from_pose(eta);
  out = k.jacobian();
  return k.status();
}

/// J^-1(eta) = blockdiag(R^T, T^-1). T^-1 needs no division, so the matrix is
/// exact even at the singularity (where it is rank deficient); the status still
/// reports near_singularity there.
template <typename Scalar>
inline Status jacobian_inverse(const Vector6<Scalar>& eta, Matrix6<Scalar>& out) noexcept {
  const auto k = EulerKinematics<Scalar>::from_pose(eta);
  out = k.jacobian_inverse();
  return k.status();
}

/// J_dot(eta, nu). A non-finite nu gives non_finite_input and a zero matrix.
template <typename Scalar>
inline Status jacobian_dot(const Vector6<Scalar>& eta, const Vector6<Scalar>& nu,
                           Matrix6<Scalar>& out) noexcept {
  if (!nu.allFinite()) {
    out.setZero();
    return Status::non_finite_input;
  }
  const auto k = EulerKinematics<Scalar>::from_pose(eta);
  out = k.jacobian_dot(nu);
  // A finite but enormous rate can overflow the products.
  if (!out.allFinite()) {
    out.setZero();
    return Status::non_finite_output;
  }
  return k.status();
}

}  // namespace neurov
