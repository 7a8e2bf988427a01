// Linear parameterisation of the vehicle function (eq. 19, 21):
//   f = M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) = Phi(nu_r_dot, nu_r, nu, eta) theta
// for NEROV's structure: centre of gravity at the origin, diagonal inertia and
// added mass, diagonal linear and quadratic damping, restoring forces from
// W - B and a vertical metacentric arm, and C(nu) in the velocity-independent
// form of eq. 39 (the form the vehicle model uses by default).
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/vehicle.hpp"

namespace neurov {

/// Number of parameters in theta.
constexpr int kRegressorParameters = 24;

/// Index of each parameter in theta.
namespace theta_index {
constexpr int mass = 0;           ///< m
constexpr int inertia = 1;        ///< I_x, I_y, I_z at 1, 2, 3
constexpr int added_mass = 4;     ///< -X_udot, -Y_vdot, -Z_wdot, -K_pdot, -M_qdot, -N_rdot at 4..9
constexpr int linear_damping = 10;     ///< 10..15
constexpr int quadratic_damping = 16;  ///< 16..21
constexpr int net_weight = 22;         ///< W - B
constexpr int restoring_arm = 23;      ///< z_g W - z_b B (metacentric moment)
}  // namespace theta_index

template <typename Scalar>
using ParameterVector = Eigen::Matrix<Scalar, kRegressorParameters, 1>;
template <typename Scalar>
using RegressorMatrix = Eigen::Matrix<Scalar, 6, kRegressorParameters>;

/// Names of the entries of theta, for logs and Python.
inline const char* theta_name(int i) noexcept {
  static const char* const names[kRegressorParameters] = {
      "m",        "I_x",      "I_y",      "I_z",      "-X_udot",  "-Y_vdot",
      "-Z_wdot",  "-K_pdot",  "-M_qdot",  "-N_rdot",  "X_u",      "Y_v",
      "Z_w",      "K_p",      "M_q",      "N_r",      "X_u|u|",   "Y_v|v|",
      "Z_w|w|",   "K_p|p|",   "M_q|q|",   "N_r|r|",   "W - B",    "z_g W - z_b B"};
  return (i >= 0 && i < kRegressorParameters) ? names[i] : "";
}

namespace detail {

/// Adds the columns col0..col0 + 2 of x × (diag(y) theta) to rows
/// row0..row0 + 2 of Phi, the form of every cross product in C(nu) nu_r:
/// row i gets x_j y_k in column k and -x_k y_j in column j (i, j, k cyclic).
template <typename Scalar, typename X, typename Y>
inline void add_cross(RegressorMatrix<Scalar>& phi, int row0, const X& x, const Y& y,
                      int col0) noexcept {
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    phi(row0 + i, col0 + k) += x(j) * y(k);
    phi(row0 + i, col0 + j) += -x(k) * y(j);
  }
}

}  // namespace detail

/// Phi such that Phi theta = M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta).
template <typename Scalar>
inline RegressorMatrix<Scalar> regressor(const Vector6<Scalar>& nu_r_dot,
                                         const Vector6<Scalar>& nu_r, const Vector6<Scalar>& nu,
                                         Scalar sin_phi, Scalar cos_phi, Scalar sin_theta,
                                         Scalar cos_theta) noexcept {
  namespace ti = theta_index;
  const Scalar p = nu(3), q = nu(4), r = nu(5);
  const Scalar ur = nu_r(0), vr = nu_r(1), wr = nu_r(2);
  // Linear and angular parts (Fossen's nu_1, nu_2).
  const auto nu1 = nu.template head<3>(), nu2 = nu.template tail<3>();
  const auto nu1_r = nu_r.template head<3>(), nu2_r = nu_r.template tail<3>();
  const Vector6<Scalar>& a = nu_r_dot;
  RegressorMatrix<Scalar> phi = RegressorMatrix<Scalar>::Zero();
  constexpr int m = ti::mass, ix = ti::inertia, xa = ti::added_mass, ka = xa + 3;

  // M nu_r_dot and C_RB(nu) nu_r = [m w x v_r; w_r x (I w)].
  phi(0, m) = a(0) + q * wr - r * vr;
  phi(1, m) = a(1) + r * ur - p * wr;
  phi(2, m) = a(2) + p * vr - q * ur;
  for (int i = 0; i < 3; ++i) phi(3 + i, ix + i) = a(3 + i);
  detail::add_cross(phi, 3, nu2_r, nu2, ix);

  // Added mass: M_A nu_r_dot and C_A(nu) nu_r = [w_r x a1; v_r x a1 + w_r x a2],
  // a1 = (X u, Y v, Z w), a2 = (K p, M q, N r) with the positive coefficients.
  for (int i = 0; i < 6; ++i) phi(i, xa + i) = a(i);
  detail::add_cross(phi, 0, nu2_r, nu1, xa);
  detail::add_cross(phi, 3, nu1_r, nu1, xa);
  detail::add_cross(phi, 3, nu2_r, nu2, ka);

  // D(nu) nu_r.
  for (int i = 0; i < 6; ++i) {
    phi(i, ti::linear_damping + i) = nu_r(i);
    phi(i, ti::quadratic_damping + i) = std::abs(nu(i)) * nu_r(i);
  }

  // g(eta).
  phi(0, ti::net_weight) = sin_theta;
  phi(1, ti::net_weight) = -cos_theta * sin_phi;
  phi(2, ti::net_weight) = -cos_theta * cos_phi;
  phi(3, ti::restoring_arm) = cos_theta * sin_phi;
  phi(4, ti::restoring_arm) = sin_theta;
  return phi;
}

/// theta of a vehicle whose structure the regressor covers; a vehicle outside
/// it (r_g != 0, off-diagonal inertia or added mass, r_b off the z axis, the
/// Kirchhoff C) is refused with the field that breaks it, `out` untouched.
template <typename Scalar>
inline ValidationError regressor_parameters(const VehicleParameters<Scalar>& p,
                                            ParameterVector<Scalar>& out) noexcept {
  namespace ti = theta_index;
  if (auto e = validate(p)) return e;
  if (!p.centre_of_gravity.isZero(Scalar(0)))
    return detail::invalid("centre_of_gravity", -1, std::nan(""),
                           "zero for the linearly parameterised model");
  const Matrix3<Scalar> inertia_off = p.inertia - Matrix3<Scalar>(p.inertia.diagonal().asDiagonal());
  if (!inertia_off.isZero(Scalar(0)))
    return detail::invalid("inertia", -1, std::nan(""), "diagonal for the linearly "
                                                        "parameterised model");
  const Matrix6<Scalar> added_off =
      p.added_mass - Matrix6<Scalar>(p.added_mass.diagonal().asDiagonal());
  if (!added_off.isZero(Scalar(0)))
    return detail::invalid("added_mass", -1, std::nan(""),
                           "diagonal for the linearly parameterised model");
  if (p.centre_of_buoyancy.x() != Scalar(0) || p.centre_of_buoyancy.y() != Scalar(0))
    return detail::invalid("centre_of_buoyancy", -1, std::nan(""),
                           "on the z axis for the linearly parameterised model");
  if (p.coriolis_form != CoriolisForm::velocity_independent)
    return detail::invalid("coriolis_form", -1, static_cast<double>(p.coriolis_form),
                           "velocity_independent for the linearly parameterised model");
  ParameterVector<Scalar> t;
  t(ti::mass) = p.mass;
  t.template segment<3>(ti::inertia) = p.inertia.diagonal();
  t.template segment<6>(ti::added_mass) = p.added_mass.diagonal();
  t.template segment<6>(ti::linear_damping) = p.linear_damping;
  t.template segment<6>(ti::quadratic_damping) = p.quadratic_damping;
  t(ti::net_weight) = p.weight - p.buoyancy;
  t(ti::restoring_arm) = p.centre_of_gravity.z() * p.weight - p.centre_of_buoyancy.z() * p.buoyancy;
  out = t;
  return {};
}

}  // namespace neurov
