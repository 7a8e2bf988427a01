// NEROV's model exactly as docs/model.md prints it (the paper's section 5,
// eq. 39), in plain double and typed in with the hydrodynamic derivatives
// (negative numbers) rather than the added-mass magnitudes the library
// stores: the independent reference the vehicle and regressor tests check
// nerov_parameters() against.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace neurov_test::nerov_paper {

using V6d = Eigen::Matrix<double, 6, 1>;
using M6d = Eigen::Matrix<double, 6, 6>;

constexpr double kM = 185, kIx = 25, kIy = 50, kIz = 50;
constexpr double kXu = -30, kYv = -80, kZw = -80, kKp = -15, kMq = -30, kNr = -30;

inline M6d nerov_m() {
  V6d d;
  d << kM - kXu, kM - kYv, kM - kZw, kIx - kKp, kIy - kMq, kIz - kNr;
  return d.asDiagonal();
}

inline M6d nerov_c_eq39(const V6d& nu) {
  const double u = nu(0), v = nu(1), w = nu(2), p = nu(3), q = nu(4), r = nu(5), m = kM;
  M6d c;
  c << 0, -m * r, m * q, 0, -kZw * w, kYv * v,          //
      m * r, 0, -m * p, kZw * w, 0, -kXu * u,           //
      -m * q, m * p, 0, -kYv * v, kXu * u, 0,           //
      0, -kZw * w, kYv * v, 0, (kIz - kNr) * r, -(kIy - kMq) * q,  //
      kZw * w, 0, -kXu * u, -(kIz - kNr) * r, 0, (kIx - kKp) * p,  //
      -kYv * v, kXu * u, 0, (kIy - kMq) * q, -(kIx - kKp) * p, 0;
  return c;
}

inline M6d nerov_d(const V6d& nu) {
  V6d d;
  d << 70 + 100 * std::abs(nu(0)), 100 + 200 * std::abs(nu(1)), 100 + 200 * std::abs(nu(2)),
      30 + 50 * std::abs(nu(3)), 50 + 100 * std::abs(nu(4)), 50 + 100 * std::abs(nu(5));
  return d.asDiagonal();
}

inline V6d nerov_g(const V6d& eta) {
  const double b = 1800;
  V6d g;
  g << 0, 0, 0, 0.02 * b * std::cos(eta(4)) * std::sin(eta(3)), 0.02 * b * std::sin(eta(4)), 0;
  return g;
}

}  // namespace neurov_test::nerov_paper
