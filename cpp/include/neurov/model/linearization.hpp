// Analytic Jacobians of the 12-state plant x = (eta, nu) under tau, for a
// linear model x_dot ~ A (x - x0) + B (tau - tau0) about any point:
//   eta_dot = J(eta) nu,
//   nu_dot  = M^-1 (tau - C(nu_r) nu_r - D(nu_r) nu_r - g(eta)) - [w x v_c; 0],
// with nu_r = nu - [v_c; 0] and v_c = R(eta)^T current_ned, as in
// Vehicle::derivative().
//
// C(nu) nu is the same vector in both Coriolis forms, so A is too: the form
// only matters to a controller's C(nu) nu_r, never to the plant.
// D(nu) nu = (D_L + D_Q |nu|) nu is continuously differentiable, with
// derivative D_L + 2 D_Q |nu|, so A is defined at rest as well.
#pragma once

#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/model/kinematics.hpp"
#include "neurov/model/vehicle.hpp"

namespace neurov {

template <typename Scalar>
using Matrix12 = Eigen::Matrix<Scalar, 12, 12>;
template <typename Scalar>
using Matrix12x6 = Eigen::Matrix<Scalar, 12, 6>;

namespace detail {

/// d(C(nu) nu)/d nu from the expanded form of Vehicle::coriolis_force():
///   top    = w x p1,                               p1 = m v + m w x r_g + a1
///   bottom = m r_g x (w x v) + w x p2 + v x a1,    p2 = I_o w + a2
/// with [a1; a2] = M_A nu. Each cross product a x b gives -S(b) da + S(a) db.
template <typename Scalar>
inline Matrix6<Scalar> coriolis_force_jacobian(const VehicleParameters<Scalar>& p,
                                               const Vector6<Scalar>& nu) noexcept {
  using Mat3 = Matrix3<Scalar>;
  using Vec3 = Vector3<Scalar>;
  const Vec3 v = nu.template head<3>(), w = nu.template tail<3>();
  const Scalar m = p.mass;
  const Vec3& rg = p.centre_of_gravity;
  const Vector6<Scalar> a = p.added_mass * nu;
  const Vec3 a1 = a.template head<3>(), a2 = a.template tail<3>();
  const Vec3 p1 = m * v + m * w.cross(rg) + a1;
  const Vec3 p2 = p.inertia * w + a2;
  const Mat3 sw = skew<Scalar>(w), sv = skew<Scalar>(v), srg = skew<Scalar>(rg);

  // dp1/dnu = [m I + M_A11, -m S(r_g) + M_A12]; dp2/dnu = [M_A21, I_o + M_A22].
  Eigen::Matrix<Scalar, 3, 6> dp1 = p.added_mass.template topRows<3>();
  dp1.template leftCols<3>().diagonal().array() += m;
  dp1.template rightCols<3>() -= m * srg;
  Eigen::Matrix<Scalar, 3, 6> dp2 = p.added_mass.template bottomRows<3>();
  dp2.template rightCols<3>() += p.inertia;
  const Eigen::Matrix<Scalar, 3, 6> da1 = p.added_mass.template topRows<3>();

  Matrix6<Scalar> jac;
  jac.template topRows<3>().noalias() = sw * dp1;
  jac.template topRightCorner<3, 3>() -= skew<Scalar>(p1);

  // m r_g x (w x v): d/dv = m S(r_g) S(w), d/dw = -m S(r_g) S(v).
  jac.template bottomRows<3>().noalias() = sw * dp2;
  jac.template bottomRows<3>().noalias() += sv * da1;
  jac.template bottomLeftCorner<3, 3>().noalias() += m * srg * sw;
  jac.template bottomLeftCorner<3, 3>() -= skew<Scalar>(a1);
  jac.template bottomRightCorner<3, 3>().noalias() -= m * srg * sv;
  jac.template bottomRightCorner<3, 3>() -= skew<Scalar>(p2);
  return jac;
}

/// d g(eta) / d(phi, theta): the columns for roll and pitch (g has no yaw or
/// position dependence). Same symbols as Vehicle::restoring().
template <typename Scalar>
inline Eigen::Matrix<Scalar, 6, 2> restoring_jacobian(const VehicleParameters<Scalar>& p,
                                                      const EulerTrig<Scalar>& t) noexcept {
  const Scalar w = p.weight, b = p.buoyancy;
  const Vector3<Scalar>& rg = p.centre_of_gravity;
  const Vector3<Scalar>& rb = p.centre_of_buoyancy;
  const Scalar wb = w - b;
  const Scalar xm = rg.x() * w - rb.x() * b;
  const Scalar ym = rg.y() * w - rb.y() * b;
  const Scalar zm = rg.z() * w - rb.z() * b;
  const Scalar sf = t.sin_phi, cf = t.cos_phi, st = t.sin_theta, ct = t.cos_theta;
  Eigen::Matrix<Scalar, 6, 2> d;
  d.col(0) << Scalar(0), -wb * ct * cf, wb * ct * sf,  //
      ym * ct * sf + zm * ct * cf,                     //
      -xm * ct * sf,                                   //
      -xm * ct * cf;
  d.col(1) << wb * ct, wb * st * sf, wb * st * cf,  //
      ym * st * cf - zm * st * sf,                  //
      zm * ct - xm * st * cf,                       //
      xm * st * sf - ym * ct;
  return d;
}

}  // namespace detail

/// A = d(eta_dot, nu_dot)/d(eta, nu) (12 x 12) and B = d(eta_dot, nu_dot)/d tau
/// (12 x 6) at (eta, nu) in a constant NED current. tau does not enter A or B
/// (the plant is affine in tau) but is checked like the other inputs.
/// Returns invalid_argument (empty vehicle) or non_finite_input with A = B = 0,
/// non_finite_output with A = B = 0 on overflow, near_singularity when the
/// attitude rows used a clamped cos(theta) (pitch at +-90 deg). Only the
/// vehicle's scalar type is deduced, so the vectors may be any expression.
template <typename Scalar>
inline Status linearize(const Vehicle<Scalar>& vehicle,
                        const typename Vehicle<Scalar>::Vec6& eta,
                        const typename Vehicle<Scalar>::Vec6& nu,
                        const typename Vehicle<Scalar>::Vec6& tau,
                        const typename Vehicle<Scalar>::Vec3& current_ned, Matrix12<Scalar>& a,
                        Matrix12x6<Scalar>& b) noexcept {
  using Vec3 = Vector3<Scalar>;
  using Mat3 = Matrix3<Scalar>;
  a.setZero();
  b.setZero();
  if (!vehicle.valid()) return Status::invalid_argument;
  if (!detail::all_finite(eta, nu, tau, current_ned)) return Status::non_finite_input;

  const VehicleParameters<Scalar>& p = vehicle.parameters();
  const Matrix6<Scalar>& m_inv = vehicle.mass_matrix_inverse();
  const EulerTrig<Scalar> trig = EulerTrig<Scalar>::from_pose(eta);
  const Mat3 r = rotation(trig);
  const Vec3 v = nu.template head<3>(), w = nu.template tail<3>();

  // R = Rz(psi) Ry(theta) Rx(phi): dR/dphi = R S(e_x), dR/dtheta = R S(Rx^T e_y),
  // dR/dpsi = S(e_z) R.
  const Vec3 ex = Vec3::UnitX(), ez = Vec3::UnitZ();
  const Vec3 pitch_axis(Scalar(0), trig.cos_phi, -trig.sin_phi);  // Rx^T e_y
  // Kinematics: eta_dot = [R v; T w].
  a.template block<3, 3>(0, 6) = r;
  a.template block<3, 3>(3, 9) = attitude_transform(trig);
  a.template block<3, 1>(0, 3).noalias() = r * ex.cross(v);
  a.template block<3, 1>(0, 4).noalias() = r * pitch_axis.cross(v);
  a.template block<3, 1>(0, 5) = ez.cross(Vec3(r * v));
  // dT/dphi and dT/dtheta are attitude_transform_dot() at unit rates.
  a.template block<3, 1>(3, 3).noalias() =
      attitude_transform_dot(trig, Scalar(1), Scalar(0)) * w;
  a.template block<3, 1>(3, 4).noalias() =
      attitude_transform_dot(trig, Scalar(0), Scalar(1)) * w;

  // Kinetics about the relative velocity.
  Vector6<Scalar> nu_r = nu;
  const Vec3 vc = r.transpose() * current_ned;
  nu_r.template head<3>() -= vc;
  Matrix6<Scalar> n = detail::coriolis_force_jacobian(p, nu_r);
  n.diagonal() += p.linear_damping + Scalar(2) * p.quadratic_damping.cwiseProduct(nu_r.cwiseAbs());

  // d nu_dot / d nu = -M^-1 N - d(w x v_c)/dw, the latter -S(v_c) in the w columns.
  a.template block<6, 6>(6, 6).noalias() = -m_inv * n;
  a.template block<3, 3>(6, 9) += skew<Scalar>(vc);

  // d nu_dot / d angle_k = M^-1 (N_v dv_c - dg) - [w x dv_c; 0], from
  // v_c = R^T c: dv_c/dphi = -e_x x v_c, dv_c/dtheta = -(Rx^T e_y) x v_c,
  // dv_c/dpsi = -R^T (e_z x c).
  Eigen::Matrix<Scalar, 3, 3> dvc;
  dvc.col(0) = -ex.cross(vc);
  dvc.col(1) = -pitch_axis.cross(vc);
  dvc.col(2).noalias() = -r.transpose() * ez.cross(current_ned);
  Eigen::Matrix<Scalar, 6, 3> rhs;
  rhs.noalias() = n.template leftCols<3>() * dvc;
  rhs.template leftCols<2>() -= detail::restoring_jacobian(p, trig);
  a.template block<6, 3>(6, 3).noalias() = m_inv * rhs;
  a.template block<3, 3>(6, 3).noalias() -= skew<Scalar>(w) * dvc;

  b.template bottomRows<6>() = m_inv;

  if (!(detail::all_finite(a) && detail::all_finite(b))) {
    a.setZero();
    b.setZero();
    return Status::non_finite_output;
  }
  return trig.status;
}

}  // namespace neurov
