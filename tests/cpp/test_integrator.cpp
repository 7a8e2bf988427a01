// rk4_step: physics it must preserve (energy without dissipation, decay with
// it), its order of accuracy, and its all-or-nothing update contract.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "neurov/model/integrator.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using namespace neurov_test;

NEUROV_SCALAR_SUITE(IntegratorTest);

/// Energies are summed in double so the float runs measure the integrator,
/// not the rounding of the energy itself.
template <typename S>
double kinetic_energy(const Vehicle<S>& v, const Vector6<S>& nu) {
  const Eigen::Matrix<double, 6, 1> n = nu.template cast<double>();
  return 0.5 * n.dot(v.mass_matrix().template cast<double>() * n);
}

/// NEROV's restoring potential, 0.02 B (1 - cos(phi) cos(theta)), written with
/// half-angle sines so small angles do not cancel: its rate is nu . g(eta).
template <typename S>
double nerov_potential(const Vector6<S>& eta) {
  const double phi = eta(3), theta = eta(4);
  const double sp = std::sin(phi / 2), st = std::sin(theta / 2);
  return 0.02 * 1800 * (2 * sp * sp * std::cos(theta) + 2 * st * st);
}

template <typename S>
Vector6<S> initial_velocity() {
  Vector6<S> nu;
  nu << S(0.8), S(-0.4), S(0.3), S(0.5), S(-0.4), S(0.6);
  return nu;
}

template <typename S>
Vector6<S> initial_pose() {
  Vector6<S> eta;
  eta << S(1), S(-2), S(3), S(0.2), S(-0.3), S(0.4);
  return eta;
}

// With tau = 0, D = 0 and g = 0 the only force is C(nu) nu, which does no
// work, so 0.5 nu^T M nu is a first integral; RK4's drift of it is O(dt^4).
TYPED_TEST(IntegratorTest, KineticEnergyIsConservedWithoutDampingOrRestoring) {
  using S = TypeParam;
  // Double: RK4's own drift (~1e-10 here) with a wide margin. Float: 1000
  // steps of rounding at ~1e-7 each, as a random walk and with margin.
  const double rel_tol = std::is_same<S, double>::value ? 1e-6 : 1e-4;
  Rng rng(41);
  std::vector<VehicleParameters<S>> cases;
  auto nerov = neurov_test::nerov_without_restoring<S>();
  for (const CoriolisForm form : {CoriolisForm::velocity_independent, CoriolisForm::kirchhoff}) {
    nerov.coriolis_form = form;
    cases.push_back(nerov);
    // r_b = r_g != 0 with W = B still has no restoring force.
    auto p = neurov_test::random_vehicle_parameters<S>(rng, form);
    p.buoyancy = p.weight;
    p.centre_of_buoyancy = p.centre_of_gravity;
    cases.push_back(p);
  }
  for (std::size_t c = 0; c < cases.size(); ++c) {
    auto& p = cases[c];
    p.linear_damping.setZero();
    p.quadratic_damping.setZero();
    const Vehicle<S> v = make_vehicle(p);
    Vector6<S> eta = initial_pose<S>(), nu = initial_velocity<S>();
    const double e0 = kinetic_energy(v, nu);
    double worst = 0.0;
    for (int step = 0; step < 1000; ++step) {
      ASSERT_EQ(rk4_step(v, eta, nu, Vector6<S>::Zero(), S(0.01)), Status::ok) << "step " << step;
      worst = std::max(worst, std::abs(kinetic_energy(v, nu) - e0) / e0);
    }
    EXPECT_LE(worst, rel_tol);
    neurov_test::record("worst_relative_drift_" + std::to_string(c), worst);
  }
}

TYPED_TEST(IntegratorTest, KineticEnergyDecaysMonotonicallyWithNerovDamping) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(neurov_test::nerov_without_restoring<S>());
  Vector6<S> eta = initial_pose<S>(), nu = initial_velocity<S>();
  double previous = kinetic_energy(v, nu);
  for (int step = 0; step < 1000; ++step) {
    ASSERT_EQ(rk4_step(v, eta, nu, Vector6<S>::Zero(), S(0.01)), Status::ok);
    const double e = kinetic_energy(v, nu);
    ASSERT_LT(e, previous) << "step " << step;
    previous = e;
  }
}

// With NEROV's restoring moment kinetic energy swaps with potential energy,
// so it is their sum that the damping must drain.
TYPED_TEST(IntegratorTest, MechanicalEnergyDecaysMonotonicallyForFullNerov) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  Vector6<S> eta = initial_pose<S>(), nu = initial_velocity<S>();
  eta(3) = S(0.6);
  eta(4) = S(-0.5);
  double previous = kinetic_energy(v, nu) + nerov_potential(eta);
  for (int step = 0; step < 1000; ++step) {
    ASSERT_EQ(rk4_step(v, eta, nu, Vector6<S>::Zero(), S(0.01)), Status::ok);
    const double e = kinetic_energy(v, nu) + nerov_potential(eta);
    ASSERT_LT(e, previous) << "step " << step;
    previous = e;
  }
}

// Quadratic damping |nu| nu has a kink at zero that caps the observed order
// once a velocity changes sign, so the order test uses a smooth (linear-damped)
// vehicle with every other term, restoring included, switched on.
TEST(IntegratorOrder, Rk4ConvergesAtFourthOrder) {
  Rng rng(42);
  std::vector<VehicleParameters<double>> cases{nerov_parameters<double>()};
  cases.push_back(neurov_test::random_vehicle_parameters<double>(rng, CoriolisForm::kirchhoff));
  cases.push_back(
      neurov_test::random_vehicle_parameters<double>(rng, CoriolisForm::velocity_independent));
  Vector6<double> tau;
  tau << 50, -20, 30, 5, -3, 4;
  const double t_end = 2.0;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    auto& p = cases[c];
    p.quadratic_damping.setZero();
    const Vehicle<double> v = make_vehicle(p);
    auto run = [&](int steps, Vector6<double>& eta, Vector6<double>& nu) {
      eta = initial_pose<double>();
      nu = initial_velocity<double>();
      const double dt = t_end / steps;
      for (int i = 0; i < steps; ++i) ASSERT_EQ(rk4_step(v, eta, nu, tau, dt), Status::ok);
    };
    Vector6<double> eta_ref, nu_ref, eta1, nu1, eta2, nu2;
    run(20 * 64, eta_ref, nu_ref);
    run(20, eta1, nu1);  // dt = 0.1
    run(40, eta2, nu2);  // dt = 0.05
    const double err1 = std::max(max_abs(eta1 - eta_ref), max_abs(nu1 - nu_ref));
    const double err2 = std::max(max_abs(eta2 - eta_ref), max_abs(nu2 - nu_ref));
    // Errors must sit far above the reference's own error and rounding.
    ASSERT_GT(err2, 1e-10);
    const double ratio = err1 / err2;
    EXPECT_GE(ratio, 12.0) << "err(dt) = " << err1 << ", err(dt/2) = " << err2;
    EXPECT_LE(ratio, 20.0) << "err(dt) = " << err1 << ", err(dt/2) = " << err2;
    neurov_test::record("ratio_" + std::to_string(c), ratio);
    neurov_test::record("error_dt_" + std::to_string(c), err1);
  }
}

TYPED_TEST(IntegratorTest, StepMatchesClassicalRk4FromDerivative) {
  using S = TypeParam;
  Rng rng(43);
  const Vehicle<S> v =
      make_vehicle(neurov_test::random_vehicle_parameters<S>(rng, CoriolisForm::velocity_independent));
  for (int i = 0; i < kPoints; ++i) {
    const Vector6<S> eta0 = rng.pose<S>(1.2), nu0 = rng.velocity<S>(), tau = rng.vec6<S>(-100, 100);
    const Vector3<S> current = i % 2 ? rng.vec3<S>(-1, 1) : Vector3<S>::Zero();
    const S dt = rng.uniform<S>(0.01, 0.2);
    Vector6<S> k[4][2];
    ASSERT_EQ(v.derivative(eta0, nu0, tau, current, k[0][0], k[0][1]), Status::ok);
    ASSERT_EQ(v.derivative(eta0 + dt / 2 * k[0][0], nu0 + dt / 2 * k[0][1], tau, current, k[1][0],
                           k[1][1]),
              Status::ok);
    ASSERT_EQ(v.derivative(eta0 + dt / 2 * k[1][0], nu0 + dt / 2 * k[1][1], tau, current, k[2][0],
                           k[2][1]),
              Status::ok);
    ASSERT_EQ(
        v.derivative(eta0 + dt * k[2][0], nu0 + dt * k[2][1], tau, current, k[3][0], k[3][1]),
        Status::ok);
    const Vector6<S> eta_expected = eta0 + dt / 6 * (k[0][0] + 2 * k[1][0] + 2 * k[2][0] + k[3][0]);
    const Vector6<S> nu_expected = nu0 + dt / 6 * (k[0][1] + 2 * k[1][1] + 2 * k[2][1] + k[3][1]);
    Vector6<S> eta = eta0, nu = nu0;
    ASSERT_EQ(rk4_step(v, eta, nu, tau, dt, current), Status::ok);
    EXPECT_TRUE(all_near(eta, eta_expected, 64 * eps<S>() * (1 + max_abs(eta_expected))))
        << "at point " << i;
    EXPECT_TRUE(all_near(nu, nu_expected, 64 * eps<S>() * (1 + max_abs(nu_expected))))
        << "at point " << i;
  }
}

TYPED_TEST(IntegratorTest, BadTimeStepIsRejectedAndStateUntouched) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  const S bad_dts[] = {S(0),
                       S(-0.0),
                       S(-0.01),
                       std::numeric_limits<S>::quiet_NaN(),
                       std::numeric_limits<S>::infinity(),
                       -std::numeric_limits<S>::infinity()};
  for (const S dt : bad_dts) {
    SCOPED_TRACE(::testing::Message() << "dt = " << dt);
    Vector6<S> eta = initial_pose<S>(), nu = initial_velocity<S>();
    EXPECT_EQ(rk4_step(v, eta, nu, Vector6<S>::Constant(S(10)), dt), Status::invalid_argument);
    EXPECT_TRUE(same_bits(eta, initial_pose<S>()));
    EXPECT_TRUE(same_bits(nu, initial_velocity<S>()));
  }
}

TYPED_TEST(IntegratorTest, NonFiniteInputsAreRejectedAndStateUntouched) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  for (const S bad : {nan, inf, -inf}) {
    for (int k = 0; k < 6; ++k) {
      SCOPED_TRACE(::testing::Message() << "tau(" << k << ") = " << bad);
      Vector6<S> eta = initial_pose<S>(), nu = initial_velocity<S>();
      Vector6<S> tau = Vector6<S>::Constant(S(10));
      tau(k) = bad;
      EXPECT_EQ(rk4_step(v, eta, nu, tau, S(0.01)), Status::non_finite_input);
      EXPECT_TRUE(same_bits(eta, initial_pose<S>()));
      EXPECT_TRUE(same_bits(nu, initial_velocity<S>()));
    }
  }
  Vector6<S> eta = initial_pose<S>(), nu = initial_velocity<S>();
  EXPECT_EQ(rk4_step(v, eta, nu, Vector6<S>::Zero(), S(0.01), Vector3<S>(S(0), nan, S(0))),
            Status::non_finite_input);
  EXPECT_TRUE(same_bits(eta, initial_pose<S>()) && same_bits(nu, initial_velocity<S>()));
  // A NaN already in the state is reported; the state is left for the caller to see.
  Vector6<S> eta_bad = initial_pose<S>();
  eta_bad(4) = nan;
  const Vector6<S> eta_bad_copy = eta_bad;
  EXPECT_EQ(rk4_step(v, eta_bad, nu, Vector6<S>::Zero(), S(0.01)), Status::non_finite_input);
  EXPECT_TRUE(same_bits(eta_bad, eta_bad_copy) && same_bits(nu, initial_velocity<S>()));
}

TYPED_TEST(IntegratorTest, OverflowIsRejectedAndStateUntouched) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  // Overflow in the first stage (a huge velocity) ...
  Vector6<S> eta = initial_pose<S>();
  const Vector6<S> huge = Vector6<S>::Constant(std::sqrt(std::numeric_limits<S>::max()));
  Vector6<S> nu = huge;
  EXPECT_EQ(rk4_step(v, eta, nu, Vector6<S>::Zero(), S(0.01)), Status::non_finite_output);
  EXPECT_TRUE(same_bits(eta, initial_pose<S>()) && same_bits(nu, huge));
  // ... and in a later one: a velocity whose first stage is finite, at the
  // longest step taken (a longer one is refused before any stage, kMaxStep).
  const Vector6<S> fast = huge / S(100);
  Vector6<S> k1e, k1n;
  ASSERT_EQ(v.derivative(eta, fast, Vector6<S>::Zero(), Vector3<S>::Zero(), k1e, k1n), Status::ok);
  nu = fast;
  EXPECT_EQ(rk4_step(v, eta, nu, Vector6<S>::Zero(), S(neurov::kMaxStep)),
            Status::non_finite_output);
  EXPECT_TRUE(same_bits(eta, initial_pose<S>()) && same_bits(nu, fast));
}

// Every stage finite, only the weighted sum k1 + 2 (k2 + k3) + k4 overflows:
// the final check alone must keep the state. A unit mass with no added mass,
// damping or restoring surging at max/3 feels no force (w = 0), so each stage
// moves x by a finite max/3 and the sum of six of them is infinite.
TYPED_TEST(IntegratorTest, OverflowInTheFinalCombinationLeavesStateUntouched) {
  using S = TypeParam;
  VehicleParameters<S> p;
  p.mass = S(1);
  p.inertia = Matrix3<S>::Identity();
  const Vehicle<S> v = make_vehicle(p);
  const Vector6<S> eta0 = Vector6<S>::Zero();
  Vector6<S> nu0 = Vector6<S>::Zero();
  nu0(0) = std::numeric_limits<S>::max() / 3;
  Vector6<S> eta = eta0, nu = nu0;
  Vector6<S> eta_dot, nu_dot;
  ASSERT_EQ(v.derivative(eta, nu, Vector6<S>::Zero(), Vector3<S>::Zero(), eta_dot, nu_dot),
            Status::ok);
  ASSERT_TRUE(nu_dot.isZero(S(0)));
  EXPECT_EQ(rk4_step(v, eta, nu, Vector6<S>::Zero(), S(1)), Status::non_finite_output);
  EXPECT_TRUE(same_bits(eta, eta0) && same_bits(nu, nu0));
}

TYPED_TEST(IntegratorTest, EmptyVehicleIsRejectedAndStateUntouched) {
  using S = TypeParam;
  const Vehicle<S> v;
  Vector6<S> eta = initial_pose<S>(), nu = initial_velocity<S>();
  EXPECT_EQ(rk4_step(v, eta, nu, Vector6<S>::Zero(), S(0.01)), Status::invalid_argument);
  EXPECT_TRUE(same_bits(eta, initial_pose<S>()) && same_bits(nu, initial_velocity<S>()));
}

TYPED_TEST(IntegratorTest, PitchAtNinetyDegreesIsFlaggedButFinite) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  Vector6<S> eta = initial_pose<S>(), nu = initial_velocity<S>();
  eta(4) = S(neurov_test::kPi / 2);
  EXPECT_EQ(rk4_step(v, eta, nu, Vector6<S>::Zero(), S(0.01)), Status::near_singularity);
  EXPECT_TRUE(eta.allFinite() && nu.allFinite());
  EXPECT_FALSE(same_bits(nu, initial_velocity<S>()));
}

TYPED_TEST(IntegratorTest, ZeroCurrentIsTheDefault) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  Vector6<S> eta1 = initial_pose<S>(), nu1 = initial_velocity<S>(), eta2 = eta1, nu2 = nu1;
  const Vector6<S> tau = Vector6<S>::Constant(S(3));
  ASSERT_EQ(rk4_step(v, eta1, nu1, tau, S(0.05)), Status::ok);
  ASSERT_EQ(rk4_step(v, eta2, nu2, tau, S(0.05), Vector3<S>::Zero()), Status::ok);
  EXPECT_TRUE(same_bits(eta1, eta2) && same_bits(nu1, nu2));
}

// In a uniform earth-frame current with no restoring and no thrust, the
// water-relative motion is the still-water problem: its kinetic energy decays
// monotonically and the vehicle ends up drifting at the current's velocity.
TYPED_TEST(IntegratorTest, VehicleDriftsWithAnEarthFrameCurrent) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(neurov_test::nerov_without_restoring<S>());
  const Vector3<S> current(S(0.4), S(-0.3), S(0.1));
  Vector6<S> eta = initial_pose<S>(), nu = Vector6<S>::Zero();
  auto relative_energy = [&] {
    Vector6<S> nu_r = nu;
    nu_r.template head<3>() -= rotation<S>(eta(3), eta(4), eta(5)).transpose() * current;
    return kinetic_energy(v, nu_r);
  };
  double previous = relative_energy();
  for (int step = 0; step < 4000; ++step) {
    ASSERT_EQ(rk4_step(v, eta, nu, Vector6<S>::Zero(), S(0.01), current), Status::ok)
        << "step " << step;
    ASSERT_TRUE(eta.allFinite() && nu.allFinite());
    const double e = relative_energy();
    if (e > 1e3 * eps<S>()) {
      ASSERT_LT(e, previous) << "step " << step;
    }
    previous = e;
  }
  const Vector3<S> velocity_ned =
      rotation<S>(eta(3), eta(4), eta(5)) * Vector3<S>(nu.template head<3>());
  // After 40 s the slowest mode (X_u: 70 / 215 per second) has decayed by e^-13.
  const double tol = std::max(1e-5, 1e3 * eps<S>());
  EXPECT_TRUE(all_near(velocity_ned, current, tol));
  EXPECT_TRUE(all_near(nu.template tail<3>(), Vector3<S>::Zero(), tol));
}

TYPED_TEST(IntegratorTest, SegmentsAreRk4StepsInTurnAndAFailureIsPlaced) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  // Two segments of 2 and 1 intervals, each interval in 2 substeps, a current on every interval.
  const Vector6<S> eta0 = initial_pose<S>(), nu0 = initial_velocity<S>();
  std::vector<S> eta0s(12), nu0s(12), tau(18), current(9, S(0.1)), out(5 * 6);
  for (int i = 0; i < 12; ++i) {
    eta0s[i] = eta0(i % 6) + S(i / 6);
    nu0s[i] = nu0(i % 6);
  }
  for (int i = 0; i < 18; ++i) tau[i] = S(i % 7) - S(3);
  const std::vector<S> dt = {S(0.1), S(0.2), S(0.1)};
  const std::int64_t steps[2] = {2, 1};
  ASSERT_EQ(rk4_segments(v, 2, eta0s.data(), nu0s.data(), steps, tau.data(), dt.data(), current.data(), 2,
                         out.data()).status,
            Status::ok);
  std::size_t k = 0, row = 0;
  for (int i = 0; i < 2; ++i) {
    Vector6<S> eta = Eigen::Map<const Vector6<S>>(eta0s.data() + 6 * i), nu = Eigen::Map<const Vector6<S>>(nu0s.data() + 6 * i);
    EXPECT_TRUE(same_bits(Vector6<S>(Eigen::Map<const Vector6<S>>(out.data() + 6 * row++)), nu));
    for (std::int64_t j = 0; j < steps[i]; ++j, ++k) {
      const Vector6<S> f = Eigen::Map<const Vector6<S>>(tau.data() + 6 * k);
      const Vector3<S> c = Eigen::Map<const Vector3<S>>(current.data() + 3 * k);
      for (int s = 0; s < 2; ++s) ASSERT_EQ(rk4_step(v, eta, nu, f, dt[k] / S(2), c), Status::ok);
      EXPECT_TRUE(same_bits(Vector6<S>(Eigen::Map<const Vector6<S>>(out.data() + 6 * row++)), nu)) << i << "," << j;
    }
  }
  const std::vector<S> bad_dt = {S(0.1), S(-1), S(0.1)};
  const SegmentFailure f = rk4_segments(v, 2, eta0s.data(), nu0s.data(), steps, tau.data(), bad_dt.data(),
                                        static_cast<const S*>(nullptr), 1, out.data());
  EXPECT_EQ(f.status, Status::invalid_argument);
  EXPECT_EQ(f.segment, 0u);
  EXPECT_EQ(f.step, 1);
}

}  // namespace
