// The linearly parameterised adaptive controller (eq. 21, 26, 28) on NEROV:
// the regressor identity Phi theta = f against the model written out from
// docs/model.md, the structure checks of regressor_parameters, the Lyapunov function
// along a closed-loop run, and exact tracking with the true parameters.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "neurov/model/integrator.hpp"
#include "neurov/model/kinematics.hpp"
#include "neurov/control/linear_adaptive_controller.hpp"
#include "neurov/control/reference_model.hpp"
#include "neurov/model/regressor.hpp"
#include "neurov/model/vehicle.hpp"
#include "nerov_paper.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::all_near;
using neurov_test::eps;
using neurov_test::max_abs;
using neurov_test::record;
using neurov_test::Rng;

using V6d = Eigen::Matrix<double, 6, 1>;
using M6d = Eigen::Matrix<double, 6, 6>;
using Theta = Eigen::Matrix<double, kRegressorParameters, 1>;
using namespace neurov_test::nerov_paper;

NEUROV_SCALAR_SUITE(RegressorTest);

TYPED_TEST(RegressorTest, NerovParametersAreThePapersNumbers) {
  using S = TypeParam;
  ParameterVector<S> theta;
  ASSERT_TRUE(regressor_parameters(nerov_parameters<S>(), theta).ok());
  Theta expected;
  expected << 185, 25, 50, 50,           // m, I
      30, 80, 80, 15, 30, 30,            // -X_udot ... -N_rdot
      70, 100, 100, 30, 50, 50,          // linear damping
      100, 200, 200, 50, 100, 100,       // quadratic damping
      0, 0.02 * 1800;                    // W - B, z_g W - z_b B
  EXPECT_TRUE(all_near(theta, expected, 8 * eps<S>() * 1800));
}

TYPED_TEST(RegressorTest, PhiTimesTrueThetaIsTheNerovModelAtRandomPoints) {
  using S = TypeParam;
  Rng rng(201);
  ParameterVector<S> theta;
  ASSERT_TRUE(regressor_parameters(nerov_parameters<S>(), theta).ok());
  const Vehicle<S> vehicle(nerov_parameters<S>());
  for (int k = 0; k < neurov_test::kPoints; ++k) {
    const V6d nu_r_dot = rng.vec6<S>(-2, 2).template cast<double>();
    const V6d nu_r = rng.vec6<S>(-1.5, 1.5).template cast<double>();
    const V6d nu = rng.vec6<S>(-1.5, 1.5).template cast<double>();
    const V6d eta = rng.pose<S>(1.4).template cast<double>();
    const auto phi = regressor<S>(nu_r_dot.cast<S>(), nu_r.cast<S>(), nu.cast<S>(),
                                  std::sin(S(eta(3))), std::cos(S(eta(3))), std::sin(S(eta(4))),
                                  std::cos(S(eta(4))));
    const V6d f = nerov_m() * nu_r_dot + nerov_c_eq39(nu) * nu_r + nerov_d(nu) * nu_r + nerov_g(eta);
    const V6d got = (phi * theta).template cast<double>();
    EXPECT_TRUE(all_near(got, f, 64 * eps<S>() * (1 + max_abs(f)))) << "point " << k;
    // The plant the controller runs against uses the same C(nu): that is
    // what makes "the structure matches exactly" true in the closed-loop tests.
    EXPECT_TRUE(all_near(vehicle.coriolis(nu.cast<S>()), nerov_c_eq39(nu),
                         16 * eps<S>() * (1 + max_abs(nerov_c_eq39(nu)))));
  }
}

// A vehicle of the same structure but other numbers, with W != B and a
// metacentric height that differs from NEROV's: every column of Phi counts.
TYPED_TEST(RegressorTest, PhiTimesThetaMatchesTheVehicleModelForAnyDiagonalVehicle) {
  using S = TypeParam;
  Rng rng(202);
  for (int k = 0; k < 50; ++k) {
    VehicleParameters<S> p;
    p.mass = rng.uniform<S>(10, 300);
    p.inertia = rng.vec3<S>(1, 80).asDiagonal();
    p.added_mass = rng.vec6<S>(1, 100).asDiagonal();
    p.weight = p.mass * S(9.81);
    p.buoyancy = p.weight * rng.uniform<S>(0.9, 1.1);
    p.centre_of_buoyancy = Vector3<S>(S(0), S(0), rng.uniform<S>(-0.1, 0.1));
    p.linear_damping = rng.vec6<S>(0, 100);
    p.quadratic_damping = rng.vec6<S>(0, 200);
    const Vehicle<S> v(p);
    ParameterVector<S> theta;
    ASSERT_TRUE(regressor_parameters(p, theta).ok());
    const Vector6<S> nu_r_dot = rng.vec6<S>(-2, 2), nu_r = rng.velocity<S>(),
                     nu = rng.velocity<S>(), eta = rng.pose<S>(1.4);
    const auto phi = regressor<S>(nu_r_dot, nu_r, nu, std::sin(eta(3)), std::cos(eta(3)),
                                  std::sin(eta(4)), std::cos(eta(4)));
    const Vector6<S> f = v.mass_matrix() * nu_r_dot + v.coriolis(nu) * nu_r +
                         v.damping(nu) * nu_r + v.restoring(eta);
    EXPECT_TRUE(all_near(phi * theta, f, 64 * eps<S>() * (1 + max_abs(f))));
  }
}

TYPED_TEST(RegressorTest, ParametersRefuseAVehicleOutsideTheStructureNamingTheField) {
  using S = TypeParam;
  using Case = neurov_test::BadField<VehicleParameters<S>>;
  const Case cases[] = {
      {"centre_of_gravity", [](VehicleParameters<S>& p) { p.centre_of_gravity.z() = S(0.01); }},
      {"coriolis_form", [](VehicleParameters<S>& p) { p.coriolis_form = CoriolisForm::kirchhoff; }},
      {"inertia",
       [](VehicleParameters<S>& p) {
         p.inertia(0, 1) = S(1);
         p.inertia(1, 0) = S(1);
       }},
      {"added_mass",
       [](VehicleParameters<S>& p) {
         p.added_mass(1, 5) = S(2);
         p.added_mass(5, 1) = S(2);
       }},
      {"centre_of_buoyancy", [](VehicleParameters<S>& p) { p.centre_of_buoyancy.x() = S(0.01); }},
      {"mass", [](VehicleParameters<S>& p) { p.mass = S(-1); }},
  };
  for (const Case& c : cases) {
    VehicleParameters<S> p = nerov_parameters<S>();
    c.mutate(p);
    ParameterVector<S> out = ParameterVector<S>::Constant(S(42));
    const ValidationError e = regressor_parameters(p, out);
    ASSERT_FALSE(e.ok()) << c.field;
    EXPECT_STREQ(e.field, c.field);
    EXPECT_TRUE((out.array() == S(42)).all()) << "out written on failure";
    char buf[256];
    e.format(buf, sizeof buf);
    EXPECT_NE(std::string(buf).find(c.field), std::string::npos) << buf;
  }
}

// ----------------------------------------------------------- closed loop

/// A smooth reference in all six DOF, with its exact derivatives.
DesiredState<double> wave(double t) {
  const double w = 0.5;
  DesiredState<double> d;
  d.eta_d << 0.5 * std::sin(w * t), 0.3 * (1 - std::cos(w * t)), 0.2 * std::sin(0.3 * t),
      0.1 * std::sin(w * t), 0.05 * std::sin(0.3 * t), 0.3 * std::sin(0.4 * t);
  d.eta_d_dot << 0.5 * w * std::cos(w * t), 0.3 * w * std::sin(w * t), 0.06 * std::cos(0.3 * t),
      0.1 * w * std::cos(w * t), 0.015 * std::cos(0.3 * t), 0.12 * std::cos(0.4 * t);
  d.eta_d_ddot << -0.5 * w * w * std::sin(w * t), 0.3 * w * w * std::cos(w * t),
      -0.018 * std::sin(0.3 * t), -0.1 * w * w * std::sin(w * t), -0.0045 * std::sin(0.3 * t),
      -0.048 * std::sin(0.4 * t);
  return d;
}

struct LyapunovRun {
  std::vector<double> v;
  bool all_ok = true;
};

/// Closed loop on NEROV with dt = 1 ms for both the controller and the RK4
/// plant (tau held over the step). V[k] = 1/2 s^T M_eta s + 1/2 theta_tilde^T
/// Gamma^-1 theta_tilde at the control instants, with theta_hat the estimate
/// the step at t_k used. `reverse_law` replaces the update by its mirror
/// image (theta_hat moves up the gradient): the same check must then fail.
LyapunovRun run_lyapunov(const Theta& theta0, const Theta& gamma, bool reverse_law) {
  const double dt = 0.001, duration = 5.0;
  const Vehicle<double> plant(nerov_parameters<double>());
  ParameterVector<double> theta_true;
  EXPECT_TRUE(regressor_parameters(plant.parameters(), theta_true).ok());
  LinearAdaptiveConfig<double> cfg;
  cfg.lambda.setOnes();
  cfg.kd << 100, 100, 100, 30, 30, 30;
  cfg.gamma = gamma;
  cfg.dt = dt;
  cfg.theta0 = theta0;
  LinearAdaptiveController<double> ctl(cfg);
  V6d eta, nu, tau;
  eta << 0.3, -0.2, 0.1, 0.1, -0.1, 0.2;
  nu << 0.1, 0, 0, 0, 0.05, 0;
  LyapunovRun run;
  const int steps = static_cast<int>(duration / dt);
  for (int k = 0; k < steps; ++k) {
    const DesiredState<double> d = wave(k * dt);
    const auto kin = EulerKinematics<double>::from_pose(eta);
    const V6d s = kin.apply(nu) - d.eta_d_dot + cfg.lambda.cwiseProduct(eta - d.eta_d);
    const M6d j_inv = kin.jacobian_inverse();
    const M6d m_eta = j_inv.transpose() * plant.mass_matrix() * j_inv;
    const Theta theta_tilde = ctl.theta() - theta_true;
    run.v.push_back(0.5 * s.dot(m_eta * s) +
                    0.5 * theta_tilde.dot(theta_tilde.cwiseQuotient(gamma)));
    const Theta before = ctl.theta();
    run.all_ok &= ctl.step(eta, nu, d, tau) == Status::ok;
    if (reverse_law) ctl.set_theta(2 * before - ctl.theta());
    run.all_ok &= rk4_step(plant, eta, nu, tau, dt) == Status::ok;
  }
  return run;
}

double max_increase(const std::vector<double>& v) {
  double m = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < v.size(); ++k) m = std::max(m, v[k + 1] - v[k]);
  return m;
}

// With the structure matching exactly and no disturbance, V_dot =
// -s^T (D_eta + K_d,eta) s <= 0. The discrete loop adds O(dt^2) per step
// (Euler step of theta_hat, zero-order hold of tau); at dt = 1 ms this stays
// below the dissipation, so V must not rise by more than 1e-9 V[0] in any step
// (rounding of V itself is ~1e-13 V[0]). The mirror-image law rises by
// 4e-7 to 5e-5 V[0] in its worst step at the same dt, at least 100 times the
// bound, so the check can tell them apart. Double
// only: a per-step change of ~1e-5 V[0] is at the resolution of float.
TEST(LinearAdaptiveLyapunov, VDoesNotIncreaseAlongTheClosedLoopFromThetaHatZero) {
  const Theta gamma = Theta::Constant(100.0);
  const LyapunovRun run = run_lyapunov(Theta::Zero(), gamma, false);
  ASSERT_TRUE(run.all_ok);
  const double v0 = run.v.front();
  record("V0", v0);
  record("max_increase_over_V0", max_increase(run.v) / v0);
  record("V_end_over_V0", run.v.back() / v0);
  EXPECT_LE(max_increase(run.v), 1e-9 * v0);
  EXPECT_LT(run.v.back(), 0.98 * v0);

  const LyapunovRun wrong = run_lyapunov(Theta::Zero(), gamma, true);
  record("reversed_max_increase_over_V0", max_increase(wrong.v) / v0);
  EXPECT_GT(max_increase(wrong.v), 100 * 1e-9 * v0);
  EXPECT_GT(wrong.v.back(), v0);
}

TEST(LinearAdaptiveLyapunov, VDoesNotIncreaseFromAPerturbedEstimateWithPerParameterGains) {
  ParameterVector<double> theta_true;
  ASSERT_TRUE(regressor_parameters(nerov_parameters<double>(), theta_true).ok());
  Rng rng(210);
  Theta theta0, gamma;
  for (int i = 0; i < kRegressorParameters; ++i) {
    theta0(i) = theta_true(i) * rng.uniform<double>(0.5, 1.5) + rng.uniform<double>(-5, 5);
    gamma(i) = rng.uniform<double>(20, 200);
  }
  const LyapunovRun run = run_lyapunov(theta0, gamma, false);
  ASSERT_TRUE(run.all_ok);
  const double v0 = run.v.front();
  record("max_increase_over_V0", max_increase(run.v) / v0);
  EXPECT_LE(max_increase(run.v), 1e-9 * v0);
  EXPECT_LT(run.v.back(), v0);
  const LyapunovRun wrong = run_lyapunov(theta0, gamma, true);
  record("reversed_max_increase_over_V0", max_increase(wrong.v) / v0);
  EXPECT_GT(max_increase(wrong.v), 100 * 1e-9 * v0);
}

NEUROV_SCALAR_SUITE(LinearAdaptiveTest);

/// NEROV driven by the frozen controller (gamma = 0) with theta_hat fixed at
/// theta0, following the reference model towards a pose with roll and pitch
/// (so the restoring moment is not zero). Returns the final max |eta - eta_d|.
template <typename S>
double frozen_tracking_error(const ParameterVector<S>& theta0) {
  const S dt = S(0.01);
  const int steps = 1500;  // 15 s
  const Vehicle<S> plant(nerov_parameters<S>());
  LinearAdaptiveConfig<S> cfg;
  cfg.lambda.setConstant(S(2));
  cfg.kd << S(400), S(400), S(400), S(100), S(100), S(100);
  cfg.gamma.setZero();
  cfg.dt = dt;
  cfg.theta0 = theta0;
  LinearAdaptiveController<S> ctl(cfg);
  ReferenceModel<S> ref(Vector6<S>::Constant(S(4)), Vector6<S>::Constant(S(4)));
  Vector6<S> r, eta, nu = Vector6<S>::Zero(), tau;
  r << S(1), S(-0.5), S(0.3), S(0.2), S(0.15), S(0.5);
  eta << S(0.3), S(-0.2), S(0.1), S(0.05), S(-0.05), S(0.1);
  DesiredState<S> d = ref.desired();
  for (int k = 0; k < steps; ++k) {
    EXPECT_EQ(ctl.step(eta, nu, d, tau), Status::ok);
    EXPECT_EQ(rk4_step(plant, eta, nu, tau, dt), Status::ok);
    EXPECT_EQ(ref.step(r, dt, d), Status::ok);
  }
  EXPECT_TRUE((ctl.theta().array() == theta0.array()).all()) << "gamma = 0 must freeze theta_hat";
  return static_cast<double>((eta - d.eta_d).cwiseAbs().maxCoeff());
}

// With theta_hat = theta and gamma = 0, tau = f - J^T K_d s cancels the model
// exactly, leaving M_eta s_dot = -(C_eta + D_eta + K_d) s: s and then eta_tilde
// decay exponentially (slowest rate ~1/s here) from the 0.3 m initial error.
// After 15 s the error is ~1e-11 in double and one ulp of the 1 m pose in
// float, so 1e-6 m holds for both. A wrong theta_hat
// leaves a steady error (the restoring moment at the commanded roll and
// pitch is then only balanced by K_d Lambda eta_tilde): 3 cm for theta_hat =
// 0 and still > 1e-4 for a 10 % error, which is how this test can fail.
TYPED_TEST(LinearAdaptiveTest, TrueParametersFrozenTrackExactly) {
  using S = TypeParam;
  ParameterVector<S> theta;
  ASSERT_TRUE(regressor_parameters(nerov_parameters<S>(), theta).ok());
  const double bound = 1e-6;
  const double exact = frozen_tracking_error<S>(theta);
  record("final_error", exact);
  EXPECT_LT(exact, bound);
  const double zero = frozen_tracking_error<S>(ParameterVector<S>::Zero());
  const double off = frozen_tracking_error<S>((theta * S(1.1)).eval());
  record("final_error_theta_zero", zero);
  record("final_error_theta_10pc", off);
  EXPECT_GT(zero, 1e-2);
  EXPECT_GT(off, 100 * bound);
}

TYPED_TEST(LinearAdaptiveTest, InvalidConfigurationNamesTheParameter) {
  using S = TypeParam;
  using Case = neurov_test::BadField<LinearAdaptiveConfig<S>>;
  const Case cases[] = {
      {"lambda", [](LinearAdaptiveConfig<S>& c) { c.lambda(1) = S(0); }},
      {"lambda", [](LinearAdaptiveConfig<S>& c) { c.lambda(4) = S(-2); }},
      {"kd", [](LinearAdaptiveConfig<S>& c) { c.kd(0) = S(-1); }},
      {"gamma", [](LinearAdaptiveConfig<S>& c) { c.gamma(7) = S(-0.5); }},
      {"gamma", [](LinearAdaptiveConfig<S>& c) { c.gamma(3) = std::numeric_limits<S>::infinity(); }},
      {"dt", [](LinearAdaptiveConfig<S>& c) { c.dt = S(0); }},
      {"dt", [](LinearAdaptiveConfig<S>& c) { c.dt = S(-0.1); }},
      {"theta0", [](LinearAdaptiveConfig<S>& c) { c.theta0(2) = std::numeric_limits<S>::quiet_NaN(); }},
  };
  for (const Case& c : cases) {
    LinearAdaptiveConfig<S> cfg;
    c.mutate(cfg);
    LinearAdaptiveController<S> out;
    const ValidationError e = LinearAdaptiveController<S>::create(cfg, out);
    EXPECT_STREQ(e.field, c.field);
    EXPECT_FALSE(out.configured());
    try {
      LinearAdaptiveController<S> thrown(cfg);
      ADD_FAILURE() << "no exception for a bad " << c.field;
    } catch (const std::invalid_argument& ex) {
      EXPECT_NE(std::string(ex.what()).find(c.field), std::string::npos) << ex.what();
    }
  }
}

TYPED_TEST(LinearAdaptiveTest, SetThetaRefusesNonFiniteAndResetRestoresTheta0) {
  using S = TypeParam;
  LinearAdaptiveConfig<S> cfg;
  cfg.theta0.setConstant(S(3));
  LinearAdaptiveController<S> ctl(cfg);
  ParameterVector<S> bad = ParameterVector<S>::Ones();
  bad(5) = std::numeric_limits<S>::quiet_NaN();
  EXPECT_FALSE(ctl.set_theta(bad));
  EXPECT_TRUE((ctl.theta().array() == S(3)).all());
  EXPECT_TRUE(ctl.set_theta(ParameterVector<S>::Ones()));
  ctl.reset();
  EXPECT_TRUE((ctl.theta().array() == S(3)).all());
}

}  // namespace
