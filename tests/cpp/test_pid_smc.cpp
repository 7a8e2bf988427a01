// The PID baseline with anti-windup and the sliding-mode controller with a
// boundary layer.
//
// Expected values are computed here in plain double from docs/model.md: J from its
// printed closed form, J_dot by a central difference of that J along
// eta_dot = J nu (so no closed form is shared with the library), the tracking
// error from eq. 11 and 14-16. For the sliding-mode controller with the true
// theta, Phi theta must be the vehicle's own M nu_r_dot + C(nu) nu_r +
// D(nu) nu_r + g(eta), so the regressor is checked against the model rather
// than against itself.
//
// This file keeps its own helpers rather than sharing test_support.hpp, so it
// builds on its own whatever that header grows (only the typed-suite macro of
// scalar_suite.hpp is shared).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "neurov/model/integrator.hpp"
#include "neurov/control/pid_controller.hpp"
#include "neurov/model/regressor.hpp"
#include "neurov/control/sliding_mode_controller.hpp"
#include "neurov/model/vehicle.hpp"
#include "scalar_suite.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;

using V6d = Eigen::Matrix<double, 6, 1>;
using M3d = Eigen::Matrix3d;
using M6d = Eigen::Matrix<double, 6, 6>;

using neurov_test::kPi;

// A seeded source whose mapping from mt19937 words to doubles is written out,
// so a seed gives the same points on every standard library.
class Draw {
 public:
  explicit Draw(std::uint32_t seed) : gen_(seed) {}
  double uniform(double lo, double hi) {
    const std::uint64_t a = gen_() >> 5, b = gen_() >> 6;
    return lo + (hi - lo) * static_cast<double>((a << 26) | b) * (1.0 / 9007199254740992.0);
  }
  V6d vec6(double lo, double hi) {
    V6d v;
    for (int i = 0; i < 6; ++i) v(i) = uniform(lo, hi);
    return v;
  }
  V6d pose(double max_pitch = 1.2) {
    V6d eta = vec6(-10, 10);
    eta(3) = uniform(-kPi, kPi);
    eta(4) = uniform(-max_pitch, max_pitch);
    eta(5) = uniform(-kPi, kPi);
    return eta;
  }

 private:
  std::mt19937 gen_;
};

// Values drawn in double are rounded to S before use, so the reference sees
// exactly the numbers the controller sees.
template <typename S>
V6d rounded(const V6d& v) {
  return v.cast<S>().template cast<double>();
}

template <typename S>
double tol(double scale) {
  // float keeps ~7 digits and the tracking error chains several products.
  const double rel = std::is_same<S, float>::value ? 2e-4 : 1e-7;
  return rel * std::max(1.0, scale);
}

double max_abs(const V6d& v) { return v.cwiseAbs().maxCoeff(); }

// --------------------------------------------------- docs/model.md in double

M6d spec_j(const V6d& eta) {
  const double cf = std::cos(eta(3)), sf = std::sin(eta(3)), ct = std::cos(eta(4)),
               st = std::sin(eta(4)), cp = std::cos(eta(5)), sp = std::sin(eta(5));
  M3d r, t;
  r << cp * ct, -sp * cf + cp * st * sf, sp * sf + cp * cf * st,  //
      sp * ct, cp * cf + sf * st * sp, -cp * sf + st * sp * cf,   //
      -st, ct * sf, ct * cf;
  t << 1, sf * st / ct, cf * st / ct,  //
      0, cf, -sf,                      //
      0, sf / ct, cf / ct;
  M6d j = M6d::Zero();
  j.topLeftCorner<3, 3>() = r;
  j.bottomRightCorner<3, 3>() = t;
  return j;
}

// d/dt J(eta(t)) with eta_dot = J(eta) nu, by a central difference.
M6d numeric_j_dot(const V6d& eta, const V6d& nu) {
  const double h = 1e-6;
  const V6d eta_dot = spec_j(eta) * nu;
  return (spec_j(eta + h * eta_dot) - spec_j(eta - h * eta_dot)) / (2 * h);
}

struct SpecTracking {
  V6d eta_tilde, eta_tilde_dot, s, nu_r, nu_r_dot;
};

// eq. 11, 14-16.
SpecTracking spec_tracking(const V6d& eta, const V6d& nu, const V6d& eta_d, const V6d& eta_d_dot,
                           const V6d& eta_d_ddot, const V6d& lambda) {
  SpecTracking e;
  const M6d j = spec_j(eta);
  const M6d j_inv = j.inverse();
  e.eta_tilde = eta - eta_d;
  e.eta_tilde_dot = j * nu - eta_d_dot;
  e.s = e.eta_tilde_dot + lambda.cwiseProduct(e.eta_tilde);
  const V6d eta_r_dot = eta_d_dot - lambda.cwiseProduct(e.eta_tilde);
  const V6d eta_r_ddot = eta_d_ddot - lambda.cwiseProduct(e.eta_tilde_dot);
  e.nu_r = j_inv * eta_r_dot;
  e.nu_r_dot = j_inv * (eta_r_ddot - numeric_j_dot(eta, nu) * e.nu_r);
  return e;
}

template <typename S>
Vector6<S> to(const V6d& v) {
  return v.cast<S>();
}

// ----------------------------------------------------------------------- PID

using neurov_test::BadField;

/// Every bad field: create() names it and leaves the controller unconfigured,
/// and the throwing constructor refuses it.
template <typename Ctl>
void expect_each_refused(const std::vector<BadField<typename Ctl::Config>>& bad_fields) {
  for (const auto& bad : bad_fields) {
    typename Ctl::Config c;
    bad.mutate(c);
    Ctl out;
    const ValidationError e = Ctl::create(c, out);
    EXPECT_EQ(std::string(e.field ? e.field : ""), bad.field);
    EXPECT_FALSE(out.configured()) << bad.field;
    EXPECT_THROW(Ctl{c}, std::invalid_argument) << bad.field;
  }
}

NEUROV_SCALAR_SUITE(PIDTest);

template <typename S>
PIDConfig<S> pid_config(Draw& d, double limit) {
  PIDConfig<S> c;
  c.kp = to<S>(d.vec6(0, 100));
  c.ki = to<S>(d.vec6(0.5, 20));
  c.kd = to<S>(d.vec6(0, 100));
  c.integral_limit.setConstant(S(limit));
  c.dt = S(0.2);
  return c;
}

TYPED_TEST(PIDTest, TauIsMinusJTransposeOfThePidTermsWithTheIntegralBeforeTheStep) {
  using S = TypeParam;
  Draw d(301);
  for (int trial = 0; trial < 20; ++trial) {
    // A limit far above anything reached, so the integral is the plain sum.
    const PIDConfig<S> cfg = pid_config<S>(d, 1e9);
    PIDController<S> pid(cfg);
    const V6d kp = cfg.kp.template cast<double>(), ki = cfg.ki.template cast<double>(),
              kd = cfg.kd.template cast<double>();
    V6d z = V6d::Zero();
    for (int k = 0; k < 10; ++k) {
      const V6d eta = rounded<S>(d.pose()), nu = rounded<S>(d.vec6(-1, 1));
      const V6d eta_d = rounded<S>(d.pose()), eta_d_dot = rounded<S>(d.vec6(-1, 1));
      const V6d eta_d_ddot = rounded<S>(d.vec6(-1, 1));
      Vector6<S> tau;
      ASSERT_EQ(pid.step(to<S>(eta), to<S>(nu), to<S>(eta_d), to<S>(eta_d_dot), to<S>(eta_d_ddot),
                         tau),
                Status::ok);
      const V6d eta_tilde = eta - eta_d;
      const V6d eta_tilde_dot = spec_j(eta) * nu - eta_d_dot;
      const V6d expected = -spec_j(eta).transpose() *
                           (kp.cwiseProduct(eta_tilde) + ki.cwiseProduct(z) +
                            kd.cwiseProduct(eta_tilde_dot));
      const V6d got = tau.template cast<double>();
      EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), tol<S>(max_abs(expected)))
          << "trial " << trial << " step " << k;
      z += 0.2 * eta_tilde;
      EXPECT_LE((pid.integral().template cast<double>() - z).cwiseAbs().maxCoeff(),
                tol<S>(max_abs(z)));
    }
  }
}

TYPED_TEST(PIDTest, AntiWindupLimitsTheIntegralTermAndStopsIntegratingIntoTheLimit) {
  using S = TypeParam;
  PIDConfig<S> cfg;
  cfg.kp.setZero();
  cfg.kd.setZero();
  cfg.ki.setConstant(S(4));
  cfg.integral_limit.setConstant(S(10));  // |K_i z| <= 10, so |z| <= 2.5
  cfg.dt = S(0.2);
  PIDController<S> pid(cfg);
  const Vector6<S> zero = Vector6<S>::Zero();
  // A constant error of +1 m in x and -1 rad in yaw for 100 s (a saturated
  // actuator would see this): a plain integrator would reach z = 100.
  Vector6<S> eta_d = zero;
  eta_d(0) = S(-1);
  eta_d(5) = S(1);
  Vector6<S> tau;
  for (int k = 0; k < 500; ++k) {
    ASSERT_EQ(pid.step(zero, zero, eta_d, zero, zero, tau), Status::ok);
    EXPECT_LE(std::abs(pid.integral()(0)), S(2.5));
    EXPECT_LE(std::abs(pid.integral()(5)), S(2.5));
  }
  EXPECT_EQ(pid.integral()(0), S(2.5));
  EXPECT_EQ(pid.integral()(5), S(-2.5));
  EXPECT_EQ(pid.integral()(1), S(0));  // no error, nothing integrated
  // At eta = 0, J = I: the integral term is exactly the limit.
  EXPECT_NEAR(static_cast<double>(tau(0)), -10.0, 1e-5);
  EXPECT_NEAR(static_cast<double>(tau(5)), 10.0, 1e-5);
  // Once the error reverses, the integral leaves the limit on the very next
  // step: there is no stored wind-up to unwind first.
  eta_d(0) = S(0.5);
  ASSERT_EQ(pid.step(zero, zero, eta_d, zero, zero, tau), Status::ok);
  EXPECT_NEAR(static_cast<double>(pid.integral()(0)), 2.5 - 0.2 * 0.5, 1e-6);
}

TYPED_TEST(PIDTest, BadConfigurationNamesTheField) {
  using S = TypeParam;
  expect_each_refused<PIDController<S>>({
      {"kp", [](PIDConfig<S>& c) { c.kp(2) = S(-1); }},
      {"ki", [](PIDConfig<S>& c) { c.ki(0) = std::numeric_limits<S>::quiet_NaN(); }},
      {"kd", [](PIDConfig<S>& c) { c.kd(5) = S(-3); }},
      {"integral_limit", [](PIDConfig<S>& c) { c.integral_limit(1) = S(0); }},
      {"dt", [](PIDConfig<S>& c) { c.dt = S(0); }},
  });
  // An unconfigured controller refuses to step.
  PIDController<S> empty;
  Vector6<S> tau = Vector6<S>::Ones();
  const Vector6<S> zero = Vector6<S>::Zero();
  EXPECT_EQ(empty.step(zero, zero, zero, zero, zero, tau), Status::invalid_argument);
  EXPECT_TRUE(tau.isZero());
}

// ----------------------------------------------------------------- sliding mode

NEUROV_SCALAR_SUITE(SlidingModeTest);

TYPED_TEST(SlidingModeTest, TauWithTheTrueThetaIsTheModelMinusJTransposeOfKdSPlusKSat) {
  using S = TypeParam;
  const Vehicle<double> nerov(nerov_parameters<double>());
  ParameterVector<double> theta;
  ASSERT_FALSE(regressor_parameters(nerov.parameters(), theta));
  Draw d(303);
  int inside = 0, outside = 0;
  for (int k = 0; k < 200; ++k) {
    SlidingModeConfig<S> cfg;
    cfg.lambda = to<S>(d.vec6(0.1, 2));
    cfg.kd = to<S>(d.vec6(0, 200));
    cfg.k = to<S>(d.vec6(0, 100));
    cfg.phi = to<S>(d.vec6(0.05, 2));
    cfg.theta = theta.cast<S>();
    SlidingModeController<S> smc(cfg);
    const V6d lambda = cfg.lambda.template cast<double>(), kd = cfg.kd.template cast<double>(),
              kgain = cfg.k.template cast<double>(), phi = cfg.phi.template cast<double>();
    const V6d eta = rounded<S>(d.pose()), nu = rounded<S>(d.vec6(-1, 1));
    // Near the desired pose so that s lands both inside and outside the layer.
    const V6d eta_d = rounded<S>(eta + d.vec6(-0.5, 0.5));
    const V6d eta_d_dot = rounded<S>(d.vec6(-1, 1)), eta_d_ddot = rounded<S>(d.vec6(-1, 1));
    Vector6<S> tau;
    ASSERT_EQ(smc.step(to<S>(eta), to<S>(nu), to<S>(eta_d), to<S>(eta_d_dot), to<S>(eta_d_ddot),
                       tau),
              Status::ok);
    const SpecTracking e = spec_tracking(eta, nu, eta_d, eta_d_dot, eta_d_ddot, lambda);
    const V6d f = nerov.mass_matrix() * e.nu_r_dot + nerov.coriolis(nu) * e.nu_r +
                  nerov.damping(nu) * e.nu_r + nerov.restoring(eta);
    V6d sat;
    for (int i = 0; i < 6; ++i) {
      const double x = e.s(i) / phi(i);
      sat(i) = std::max(-1.0, std::min(1.0, x));
      (std::abs(x) < 1 ? inside : outside) += 1;
    }
    const V6d expected =
        f - spec_j(eta).transpose() * (kd.cwiseProduct(e.s) + kgain.cwiseProduct(sat));
    const double scale = std::max(max_abs(expected), max_abs(f));
    EXPECT_LE((tau.template cast<double>() - expected).cwiseAbs().maxCoeff(), tol<S>(scale))
        << "point " << k;
    EXPECT_LE((smc.model_output().template cast<double>() - f).cwiseAbs().maxCoeff(),
              tol<S>(max_abs(f)));
  }
  // Both branches of sat were exercised.
  EXPECT_GT(inside, 50);
  EXPECT_GT(outside, 50);
}

// What the boundary layer is for: a constant force the model does not know
// is held to |s| of order d / (K_d + K / phi) instead of d / K_d.
TEST(SlidingModeClosedLoop, BoundaryLayerShrinksTheErrorFromAnUnmodelledForce) {
  const Vehicle<double> nerov(nerov_parameters<double>());
  ParameterVector<double> theta;
  ASSERT_FALSE(regressor_parameters(nerov.parameters(), theta));
  const double force = 100.0, dt = 0.05;
  const auto final_s = [&](double k_switch) {
    SlidingModeConfig<double> cfg;
    cfg.lambda.setConstant(0.5);
    cfg.kd.setConstant(100.0);
    cfg.k.setConstant(k_switch);
    cfg.phi.setConstant(0.1);
    cfg.theta = theta;
    SlidingModeController<double> smc(cfg);
    V6d eta = V6d::Zero(), nu = V6d::Zero(), tau;
    const V6d zero = V6d::Zero();
    V6d d = V6d::Zero();
    d(0) = force;
    for (int k = 0; k < static_cast<int>(60.0 / dt); ++k) {
      EXPECT_EQ(smc.step(eta, nu, zero, zero, zero, tau), Status::ok);
      for (int sub = 0; sub < 5; ++sub)
        EXPECT_EQ(rk4_step(nerov, eta, nu, (tau + d).eval(), dt / 5), Status::ok);
    }
    return smc.tracking().s(0);
  };
  const double without = final_s(0.0), with = final_s(200.0);
  // Without switching, K_d s balances the force plus the damping on
  // nu - nu_r = J^-1 s: (70 + 100) s = 100 at rest in surge.
  EXPECT_NEAR(without, force / (100.0 + 70.0), 0.02);
  // With K = 200 and phi = 0.1, inside the layer the gain is K_d + K / phi.
  EXPECT_NEAR(with, force / (100.0 + 2000.0 + 70.0), 0.005);
  EXPECT_LT(std::abs(with), 0.1 * std::abs(without));
}

TYPED_TEST(SlidingModeTest, BadConfigurationNamesTheField) {
  using S = TypeParam;
  expect_each_refused<SlidingModeController<S>>({
      {"lambda", [](SlidingModeConfig<S>& c) { c.lambda(0) = S(0); }},
      {"kd", [](SlidingModeConfig<S>& c) { c.kd(3) = S(-1); }},
      {"k", [](SlidingModeConfig<S>& c) { c.k(2) = S(-5); }},
      {"phi", [](SlidingModeConfig<S>& c) { c.phi(4) = S(0); }},
      {"theta", [](SlidingModeConfig<S>& c) { c.theta(7) = std::numeric_limits<S>::infinity(); }},
  });
}

}  // namespace
