// The NN controller's reference for the tests: J, J^-1 and J_dot from their
// printed closed forms in docs/model.md, the tracking error from eq. 11 and
// 14-16, the basis from eq. 30, tau from eq. 35 and the weight step from eq.
// 37, in plain double loops, and random cases to compare the library with.
// Nothing of the library's kinematics or tracking error is used for the
// expected numbers, so a shared mistake cannot cancel out.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "neurov/model/integrator.hpp"
#include "neurov/control/linear_adaptive_controller.hpp"
#include "neurov/control/nn_controller.hpp"
#include "neurov/control/pd_controller.hpp"
#include "neurov/control/rbf_network.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/model/vehicle.hpp"
#include "test_support.hpp"


namespace neurov_test::nn {

using namespace neurov;
using neurov_test::all_near;
using neurov_test::eps;
using neurov_test::kPi;
using neurov_test::max_abs;
using neurov_test::record;
using neurov_test::Rng;

using V3d = Eigen::Vector3d;
using M3d = Eigen::Matrix3d;
using V6d = Eigen::Matrix<double, 6, 1>;
using M6d = Eigen::Matrix<double, 6, 6>;
using MatXd = Eigen::MatrixXd;
using VecXd = Eigen::VectorXd;


// ------------------------------------------- docs/model.md in plain double

inline M3d spec_rotation(double phi, double theta, double psi) {
  const double cf = std::cos(phi), sf = std::sin(phi), ct = std::cos(theta), st = std::sin(theta),
               cp = std::cos(psi), sp = std::sin(psi);
  M3d r;
  r << cp * ct, -sp * cf + cp * st * sf, sp * sf + cp * cf * st,  //
      sp * ct, cp * cf + sf * st * sp, -cp * sf + st * sp * cf,   //
      -st, ct * sf, ct * cf;
  return r;
}

inline M3d spec_t(double phi, double theta) {
  const double cf = std::cos(phi), sf = std::sin(phi), ct = std::cos(theta), tt = std::tan(theta);
  M3d t;
  t << 1, sf * tt, cf * tt,  //
      0, cf, -sf,            //
      0, sf / ct, cf / ct;
  return t;
}

inline M3d spec_t_inv(double phi, double theta) {
  const double cf = std::cos(phi), sf = std::sin(phi), ct = std::cos(theta), st = std::sin(theta);
  M3d t;
  t << 1, 0, -st,  //
      0, cf, ct * sf,  //
      0, -sf, ct * cf;
  return t;
}

inline M6d block_diag(const M3d& a, const M3d& b) {
  M6d m = M6d::Zero();
  m.topLeftCorner<3, 3>() = a;
  m.bottomRightCorner<3, 3>() = b;
  return m;
}

inline M6d spec_j(const V6d& eta) {
  return block_diag(spec_rotation(eta(3), eta(4), eta(5)), spec_t(eta(3), eta(4)));
}

inline M6d spec_j_inv(const V6d& eta) {
  return block_diag(spec_rotation(eta(3), eta(4), eta(5)).transpose(), spec_t_inv(eta(3), eta(4)));
}

/// J_dot = blockdiag(R S(omega), dT/dphi phi_dot + dT/dtheta theta_dot).
inline M6d spec_j_dot(const V6d& eta, const V6d& nu) {
  const double phi = eta(3), theta = eta(4);
  const V3d w = nu.tail<3>();
  const V3d euler_rate = spec_t(phi, theta) * w;
  const double cf = std::cos(phi), sf = std::sin(phi), ct = std::cos(theta), st = std::sin(theta),
               tt = std::tan(theta);
  M3d dphi, dtheta, sw;
  dphi << 0, cf * tt, -sf * tt,  //
      0, -sf, -cf,               //
      0, cf / ct, -sf / ct;
  dtheta << 0, sf / (ct * ct), cf / (ct * ct),  //
      0, 0, 0,                                  //
      0, sf * st / (ct * ct), cf * st / (ct * ct);
  sw << 0, -w(2), w(1), w(2), 0, -w(0), -w(1), w(0), 0;
  return block_diag(spec_rotation(phi, theta, eta(5)) * sw,
                    dphi * euler_rate(0) + dtheta * euler_rate(1));
}

inline V6d matvec(const M6d& a, const V6d& v) {
  V6d out;
  for (int i = 0; i < 6; ++i) {
    double acc = 0;
    for (int k = 0; k < 6; ++k) acc += a(i, k) * v(k);
    out(i) = acc;
  }
  return out;
}

inline V6d matvec_t(const M6d& a, const V6d& v) { return matvec(M6d(a.transpose()), v); }

/// Eq. 11 and 14-16, written from docs/model.md.
struct SpecTracking {
  V6d eta_tilde, eta_tilde_dot, s, nu_r, nu_r_dot;
  M6d j, j_inv;
};

inline SpecTracking spec_tracking(const V6d& eta, const V6d& nu, const V6d& eta_d, const V6d& eta_d_dot,
                           const V6d& eta_d_ddot, const V6d& lambda) {
  SpecTracking e;
  e.j = spec_j(eta);
  e.j_inv = spec_j_inv(eta);
  e.eta_tilde = eta - eta_d;
  e.eta_tilde_dot = matvec(e.j, nu) - eta_d_dot;
  e.s = e.eta_tilde_dot + lambda.cwiseProduct(e.eta_tilde);
  const V6d eta_r_dot = eta_d_dot - lambda.cwiseProduct(e.eta_tilde);
  const V6d eta_r_ddot = eta_d_ddot - lambda.cwiseProduct(e.eta_tilde_dot);
  e.nu_r = matvec(e.j_inv, eta_r_dot);
  e.nu_r_dot = matvec(e.j_inv, eta_r_ddot - matvec(spec_j_dot(eta, nu), e.nu_r));
  return e;
}

/// The inputs of one NN step, drawn in double and rounded to S so that the
/// controller under test and the double reference see the same numbers.
struct NNCase {
  V6d eta, nu, eta_d, eta_d_dot, eta_d_ddot, lambda, kd;
  MatXd centres;  // N x 24
  VecXd widths;
  MatXd weights;  // 6 x N
  double gamma = 0, dt = 0;
};

template <typename S>
double draw(Rng& rng, double lo, double hi) {
  return static_cast<double>(rng.uniform<S>(lo, hi));
}

template <typename S>
V6d draw6(Rng& rng, double lo, double hi) {
  return rng.vec6<S>(lo, hi).template cast<double>();
}

inline VecXd network_input(const SpecTracking& e, const V6d& nu, const V6d& eta) {
  VecXd x(24);
  x << e.nu_r_dot, e.nu_r, nu, eta;
  return x;
}

/// A random state, and centres most of which sit within a few widths of the
/// network input x so that g(x) is far from 0 and from 1; the last ones are
/// far away (g ~ 0), as most centres of a real network are.
template <typename S>
NNCase random_case(Rng& rng, int n_centres = 12) {
  NNCase c;
  c.eta = rng.pose<S>(1.2).template cast<double>();
  c.nu = rng.velocity<S>().template cast<double>();
  c.eta_d = c.eta + draw6<S>(rng, -0.5, 0.5);
  c.eta_d = c.eta_d.cast<S>().template cast<double>();
  c.eta_d_dot = draw6<S>(rng, -1.0, 1.0);
  c.eta_d_ddot = draw6<S>(rng, -1.0, 1.0);
  c.lambda = draw6<S>(rng, 0.5, 2.0);
  c.kd = draw6<S>(rng, 0.0, 50.0);
  c.gamma = draw<S>(rng, 0.5, 2.0);
  c.dt = draw<S>(rng, 0.05, 0.2);
  const SpecTracking e = spec_tracking(c.eta, c.nu, c.eta_d, c.eta_d_dot, c.eta_d_ddot, c.lambda);
  const VecXd x = network_input(e, c.nu, c.eta);
  c.centres.resize(n_centres, 24);
  for (int j = 0; j < n_centres; ++j)
    for (int i = 0; i < 24; ++i)
      c.centres(j, i) = j < n_centres - 3 ? static_cast<double>(static_cast<S>(x(i) + draw<double>(rng, -1.5, 1.5)))
                                          : draw<S>(rng, -10.0, 10.0);
  c.widths.resize(n_centres);
  for (int j = 0; j < n_centres; ++j) c.widths(j) = draw<S>(rng, 2.0, 6.0);
  c.weights.resize(6, n_centres);
  for (int j = 0; j < n_centres; ++j)
    for (int i = 0; i < 6; ++i) c.weights(i, j) = draw<S>(rng, -5.0, 5.0);
  return c;
}

/// A new state for the same network (for multi-step sequences).
template <typename S>
void redraw_state(Rng& rng, NNCase& c) {
  c.eta = c.eta + draw6<S>(rng, -0.1, 0.1);
  c.eta(4) = std::max(-1.2, std::min(1.2, c.eta(4)));
  c.eta = c.eta.cast<S>().template cast<double>();
  c.nu = rng.velocity<S>().template cast<double>();
  c.eta_d_dot = draw6<S>(rng, -1.0, 1.0);
  c.eta_d_ddot = draw6<S>(rng, -1.0, 1.0);
}

struct NNExpected {
  V6d tau, f_hat, a;  // a = J^-1 s (no dt)
  VecXd g;
  MatXd weights;  // after the step
  SpecTracking e;
  bool adapted = true;
};

struct Modification {
  RobustModification kind = RobustModification::none;
  double sigma_m = 0, kappa = 0, w_max = 0, dead_zone = 0;

  static Modification sigma(double sigma_m) { return {RobustModification::sigma, sigma_m, 0, 0, 0}; }
  static Modification e_modification(double kappa) {
    return {RobustModification::e_modification, 0, kappa, 0, 0};
  }
  static Modification projection(double w_max) {
    return {RobustModification::projection, 0, 0, w_max, 0};
  }
  /// No robust modification, adaptation off while |s| < dead_zone.
  static Modification with_dead_zone(double dead_zone) {
    return {RobustModification::none, 0, 0, 0, dead_zone};
  }

  /// Writes this modification into a controller's configuration, in S.
  template <typename S>
  void apply_to(NNAdaptiveConfig<S>& cfg) const {
    cfg.modification = kind;
    cfg.sigma_m = static_cast<S>(sigma_m);
    cfg.kappa = static_cast<S>(kappa);
    cfg.w_max = static_cast<S>(w_max);
    cfg.dead_zone = static_cast<S>(dead_zone);
  }
};

/// Eq. 30, 35 and 37 with plain loops. `w` is the weight matrix before the
/// step; tau uses it, the update produces the returned one.
inline NNExpected nn_reference(const NNCase& c, const MatXd& w, const VecXd& rates,
                        const Modification& mod) {
  NNExpected out;
  out.e = spec_tracking(c.eta, c.nu, c.eta_d, c.eta_d_dot, c.eta_d_ddot, c.lambda);
  double x[24];
  for (int i = 0; i < 6; ++i) {
    x[i] = out.e.nu_r_dot(i);
    x[6 + i] = out.e.nu_r(i);
    x[12 + i] = c.nu(i);
    x[18 + i] = c.eta(i);
  }
  const int n = static_cast<int>(c.centres.rows());
  out.g.resize(n);
  for (int j = 0; j < n; ++j) {
    double d2 = 0;
    for (int i = 0; i < 24; ++i) d2 += (x[i] - c.centres(j, i)) * (x[i] - c.centres(j, i));
    out.g(j) = std::exp(-d2 / (2 * c.widths(j) * c.widths(j)));
  }
  for (int i = 0; i < 6; ++i) {
    double acc = 0;
    for (int j = 0; j < n; ++j) acc += w(i, j) * out.g(j);
    out.f_hat(i) = acc;
  }
  const V6d kds = c.kd.cwiseProduct(out.e.s);
  out.tau = out.f_hat - matvec_t(out.e.j, kds);  // W g - J^T K_d s
  out.a = matvec(out.e.j_inv, out.e.s);
  out.weights = w;
  out.adapted = !(mod.dead_zone > 0 && out.e.s.norm() < mod.dead_zone);
  if (!out.adapted) return out;
  double leak = 0;
  if (mod.kind == RobustModification::sigma) leak = mod.sigma_m;
  if (mod.kind == RobustModification::e_modification) leak = mod.kappa * out.a.norm();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < 6; ++i)
      out.weights(i, j) = w(i, j) * (1 - c.dt * leak * rates(j)) - c.dt * rates(j) * out.a(i) * out.g(j);
  if (mod.kind == RobustModification::projection) {
    double norm2 = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < 6; ++i) norm2 += out.weights(i, j) * out.weights(i, j);
    if (std::sqrt(norm2) > mod.w_max) out.weights *= mod.w_max / std::sqrt(norm2);
  }
  return out;
}

template <typename S, int N = Eigen::Dynamic>
typename NNAdaptiveController<S, N>::Network make_network(const MatXd& centres, const VecXd& widths,
                                                          const MatXd& weights) {
  using Net = typename NNAdaptiveController<S, N>::Network;
  Net net;
  const typename Net::CentreMatrix c = centres.cast<S>();
  const typename Net::BasisVector w = widths.cast<S>();
  const ValidationError err = Net::create(c, w, net);
  EXPECT_TRUE(err.ok()) << (err.field ? err.field : "");
  EXPECT_TRUE(net.set_weights(weights.cast<S>()));
  return net;
}

/// A configuration written in double, in S.
template <typename S>
NNAdaptiveConfig<S> cast_config(const NNAdaptiveConfig<double>& d) {
  NNAdaptiveConfig<S> c;
  c.lambda = d.lambda.cast<S>();
  c.kd = d.kd.cast<S>();
  c.gamma = static_cast<S>(d.gamma);
  c.dt = static_cast<S>(d.dt);
  c.modification = d.modification;
  c.sigma_m = static_cast<S>(d.sigma_m);
  c.kappa = static_cast<S>(d.kappa);
  c.w_max = static_cast<S>(d.w_max);
  c.dead_zone = static_cast<S>(d.dead_zone);
  return c;
}

template <typename S>
NNAdaptiveConfig<S> config_of(const NNCase& c, const Modification& mod = {}) {
  NNAdaptiveConfig<S> cfg;
  cfg.lambda = c.lambda.cast<S>();
  cfg.kd = c.kd.cast<S>();
  cfg.gamma = static_cast<S>(c.gamma);
  cfg.dt = static_cast<S>(c.dt);
  mod.apply_to(cfg);
  return cfg;
}

/// The learning rate of every centre when they all share gamma.
inline VecXd uniform_rates(const NNCase& c) { return VecXd::Constant(c.centres.rows(), c.gamma); }

template <typename S, int N = Eigen::Dynamic>
NNAdaptiveController<S, N> make_nn(const NNCase& c, const Modification& mod = {}) {
  NNAdaptiveController<S, N> ctl;
  const ValidationError err =
      NNAdaptiveController<S, N>::create(make_network<S, N>(c.centres, c.widths, c.weights),
                                         config_of<S>(c, mod), ctl);
  EXPECT_TRUE(err.ok()) << (err.field ? err.field : "");
  return ctl;
}

template <typename S, typename Ctl>
Status step_case(Ctl& ctl, const NNCase& c, Vector6<S>& tau) {
  return ctl.step(c.eta.cast<S>().eval(), c.nu.cast<S>().eval(), c.eta_d.cast<S>().eval(),
                  c.eta_d_dot.cast<S>().eval(), c.eta_d_ddot.cast<S>().eval(), tau);
}

/// Tolerance for comparing an S computation with the double reference: a
/// hundred ulps of S relative to the size of the numbers. Float rounds x, a
/// 24-term distance and an exponential on the way; the margin is small enough
/// that using the updated weights for tau, or any other term of the laws
/// changed by a fraction of a percent, is far outside it (checked below).
template <typename S>
double tol(double scale) {
  return 100.0 * static_cast<double>(eps<S>()) * (1.0 + scale);
}


}  // namespace neurov_test::nn
