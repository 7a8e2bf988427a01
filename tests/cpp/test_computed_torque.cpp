// The computed-torque controller: its tau against the nominal vehicle's M, C,
// D and g evaluated here in double, against the regressor's independent
// NEROV model, and in a closed loop on the exact model, where s must decay.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "neurov/control/computed_torque_controller.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/model/integrator.hpp"
#include "neurov/model/regressor.hpp"
#include "neurov/model/vehicle.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::all_near;
using neurov_test::eps;
using neurov_test::max_abs;
using neurov_test::Rng;
using V6d = Eigen::Matrix<double, 6, 1>;

NEUROV_SCALAR_SUITE(ComputedTorqueTest);

/// Relative tolerance of a float or double step against a double reference.
template <typename S>
double tol(double scale) {
  return 1e3 * static_cast<double>(eps<S>()) * (1.0 + scale);
}

TYPED_TEST(ComputedTorqueTest, TauIsTheNominalInverseDynamicsMinusJTransposeKdS) {
  using S = TypeParam;
  Rng rng(610);
  for (const CoriolisForm form : {CoriolisForm::velocity_independent, CoriolisForm::kirchhoff}) {
    for (int k = 0; k < neurov_test::kPoints / 4; ++k) {
      ComputedTorqueConfig<S> cfg;
      cfg.vehicle = neurov_test::random_vehicle_parameters<S>(rng, form);
      cfg.lambda = rng.vec6<S>(0.1, 2.0);
      cfg.kd = rng.vec6<S>(0.0, 300.0);
      ComputedTorqueController<S> ct(cfg);
      const Vector6<S> eta = rng.pose<S>(1.2), nu = rng.velocity<S>();
      const Vector6<S> eta_d = rng.pose<S>(1.2), eta_d_dot = rng.vec6<S>(-1, 1),
                       eta_d_ddot = rng.vec6<S>(-1, 1);
      Vector6<S> tau;
      ASSERT_EQ(ct.step(eta, nu, eta_d, eta_d_dot, eta_d_ddot, tau), Status::ok);

      // The same law in double, term by term from the vehicle's own matrices.
      const Vehicle<double> v(cfg.vehicle.template cast<double>());
      TrackingError<double> e;
      ASSERT_EQ(compute_tracking_error<double>(
                    eta.template cast<double>(), nu.template cast<double>(),
                    eta_d.template cast<double>(), eta_d_dot.template cast<double>(),
                    eta_d_ddot.template cast<double>(), cfg.lambda.template cast<double>(), e),
                Status::ok);
      const V6d nud = nu.template cast<double>();
      const V6d f = v.mass_matrix() * e.nu_r_dot + v.coriolis(nud) * e.nu_r +
                    v.damping(nud) * e.nu_r + v.restoring(eta.template cast<double>());
      const Eigen::Matrix<double, 6, 6> j = e.kinematics.jacobian();
      const V6d expected = f - j.transpose() * cfg.kd.template cast<double>().cwiseProduct(e.s);
      EXPECT_TRUE(all_near(tau, expected, tol<S>(max_abs(expected))));
      EXPECT_TRUE(all_near(ct.model_output(), f, tol<S>(max_abs(f))));
      EXPECT_EQ(ct.adaptive_norm(), S(0));
      EXPECT_EQ(ct.logged_parameters().size(), 0);
    }
  }
}

TYPED_TEST(ComputedTorqueTest, OnNerovTheModelIsTheRegressorWithTheTrueTheta) {
  using S = TypeParam;
  Rng rng(611);
  ComputedTorqueConfig<S> cfg;
  cfg.vehicle = nerov_parameters<S>();
  ComputedTorqueController<S> ct(cfg);
  ParameterVector<S> theta;
  ASSERT_TRUE(regressor_parameters(cfg.vehicle, theta).ok());
  for (int k = 0; k < neurov_test::kPoints; ++k) {
    const Vector6<S> eta = rng.pose<S>(1.2), nu = rng.velocity<S>(), eta_d = rng.pose<S>(1.2);
    const Vector6<S> eta_d_dot = rng.vec6<S>(-1, 1), eta_d_ddot = rng.vec6<S>(-1, 1);
    Vector6<S> tau;
    ASSERT_EQ(ct.step(eta, nu, eta_d, eta_d_dot, eta_d_ddot, tau), Status::ok);
    const auto& e = ct.tracking();
    const auto& trig = e.kinematics.trig;
    const Vector6<S> f = regressor<S>(e.nu_r_dot, e.nu_r, nu, trig.sin_phi, trig.cos_phi,
                                      trig.sin_theta, trig.cos_theta) *
                         theta;
    EXPECT_TRUE(all_near(ct.model_output(), f, tol<S>(max_abs(f))));
  }
}

/// A smooth desired trajectory with its derivatives at t.
struct Trajectory {
  V6d amplitude, omega;
  void at(double t, V6d& eta_d, V6d& eta_d_dot, V6d& eta_d_ddot) const {
    for (int i = 0; i < 6; ++i) {
      eta_d(i) = amplitude(i) * std::sin(omega(i) * t);
      eta_d_dot(i) = amplitude(i) * omega(i) * std::cos(omega(i) * t);
      eta_d_ddot(i) = -amplitude(i) * omega(i) * omega(i) * std::sin(omega(i) * t);
    }
  }
};

/// The largest ||s|| over [t_from, t_end] of a closed loop on the exact model
/// from an initial error, the force held over each control period dt; the
/// reference moves, or is a fixed pose (`moving` false).
double late_s_norm(CoriolisForm form, bool moving, double dt, double& initial_s_norm) {
  Rng rng(612);
  ComputedTorqueConfig<double> cfg;
  cfg.vehicle = neurov_test::random_vehicle_parameters<double>(rng, form);
  cfg.lambda.setConstant(1.0);
  cfg.kd.setConstant(300.0);
  ComputedTorqueController<double> ct(cfg);
  const Vehicle<double> plant(cfg.vehicle);
  Trajectory traj;
  traj.amplitude << 2.0, 1.0, 0.5, 0.1, 0.1, 0.5;
  if (!moving) traj.amplitude.setZero();
  traj.omega << 0.2, 0.3, 0.25, 0.4, 0.35, 0.15;
  V6d eta, nu = V6d::Zero();
  eta << 0.5, -0.5, 0.3, 0.05, -0.05, 0.2;
  const double t_end = 40.0, t_from = 30.0;
  const int substeps = 5;
  double late = 0.0;
  initial_s_norm = -1.0;
  for (int k = 0; k * dt <= t_end + 1e-9; ++k) {
    const double t = k * dt;
    V6d eta_d, eta_d_dot, eta_d_ddot, tau;
    traj.at(t, eta_d, eta_d_dot, eta_d_ddot);
    if (ct.step(eta, nu, eta_d, eta_d_dot, eta_d_ddot, tau) != Status::ok) return 1e300;
    const double s = ct.tracking().s.norm();
    if (initial_s_norm < 0) initial_s_norm = s;
    if (t >= t_from) late = std::max(late, s);
    for (int j = 0; j < substeps; ++j)
      if (rk4_step(plant, eta, nu, tau, dt / substeps) != Status::ok) return 1e300;
  }
  return late;
}

TEST(ComputedTorqueClosedLoop, DrivesSToZeroOnTheExactModel) {
  for (const CoriolisForm form : {CoriolisForm::velocity_independent, CoriolisForm::kirchhoff}) {
    SCOPED_TRACE(form == CoriolisForm::kirchhoff ? "kirchhoff" : "velocity_independent");
    double initial = 0.0, initial_half = 0.0;
    // A fixed pose: the held force is exact at rest, so s goes to zero.
    const double still = late_s_norm(form, false, 0.05, initial);
    neurov_test::record("late_s_fixed_pose", still);
    EXPECT_GT(initial, 0.1);
    EXPECT_LT(still, 1e-9 * initial);
    // A moving reference: what is left is the zero-order hold's error, of
    // order dt (measured 1.2e-3 of the initial ||s|| at dt = 0.05 s).
    const double moving = late_s_norm(form, true, 0.05, initial);
    const double moving_half = late_s_norm(form, true, 0.025, initial_half);
    neurov_test::record("late_s_moving", moving);
    EXPECT_LT(moving, 2e-3 * initial);
    EXPECT_LT(moving_half, 0.6 * moving);
  }
}

TYPED_TEST(ComputedTorqueTest, BadConfigurationNamesTheField) {
  using S = TypeParam;
  const auto field_of = [](const ComputedTorqueConfig<S>& c) {
    ComputedTorqueController<S> out;
    const ValidationError e = ComputedTorqueController<S>::create(c, out);
    EXPECT_EQ(out.configured(), e.ok());  // a rejected configuration leaves `out` untouched
    return std::string(e.field ? e.field : "");
  };
  ComputedTorqueConfig<S> c;
  c.vehicle = nerov_parameters<S>();
  EXPECT_EQ(field_of(c), "");
  c.lambda(2) = S(0);
  EXPECT_EQ(field_of(c), "lambda");
  c.lambda(2) = S(1);
  c.kd(5) = S(-1);
  EXPECT_EQ(field_of(c), "kd");
  c.kd(5) = std::numeric_limits<S>::quiet_NaN();
  EXPECT_EQ(field_of(c), "kd");
  c.kd(5) = S(0);
  c.vehicle.mass = S(-1);
  EXPECT_EQ(field_of(c), "mass");
  c.vehicle = nerov_parameters<S>();
  c.vehicle.linear_damping(1) = S(-3);
  EXPECT_EQ(field_of(c), "linear_damping");
  try {
    ComputedTorqueController<S>{c};
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& ex) {
    EXPECT_EQ(std::string(ex.what()).rfind("computed-torque controller: linear_damping[1]", 0),
              0u)
        << ex.what();
  }
  // An unconfigured controller refuses to step.
  ComputedTorqueController<S> empty;
  Vector6<S> tau = Vector6<S>::Constant(S(3));
  const Vector6<S> z = Vector6<S>::Zero();
  EXPECT_EQ(empty.step(z, z, z, z, z, tau), Status::invalid_argument);
  EXPECT_TRUE(tau.isZero(S(0)));
}

}  // namespace
