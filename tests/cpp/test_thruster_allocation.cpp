// Thrusters with curves: the allocation goes tau -> thrusts (pseudo-inverse,
// saturation) -> commands through each curve's inverse, and the plant
// produces curve(command). Checked against tau itself (inside the attainable
// set), its direction (outside), the curve evaluated independently, and the
// closed loop's tau_applied; bad curve configurations are named errors.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "neurov/model/bluerov2_heavy.hpp"
#include "neurov/model/thrusters.hpp"
#include "neurov/sim/simulator.hpp"
#include "curve_tables.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::pwm_test_curve;

template <typename S>
ThrusterConfig<S> curved_layout(S voltage) {
  const auto layout = bluerov2_heavy_layout<S>();
  Eigen::Matrix<S, 6, 8> b;
  EXPECT_TRUE(allocation_matrix(layout, b).ok());
  ThrusterConfig<S> c;
  c.matrix = b;
  c.curves.assign(8, pwm_test_curve<S>());
  c.supply_voltage = voltage;
  return c;
}

template <typename S>
S tol(double scale) {
  return static_cast<S>(std::is_same<S, float>::value ? 2e-5 * scale : 1e-9 * scale);
}

NEUROV_SCALAR_SUITE(ThrusterAllocationTest);

TYPED_TEST(ThrusterAllocationTest, LimitsComeFromTheCurvesAtTheSupplyVoltage) {
  using S = TypeParam;
  Thrusters<S> t;
  ASSERT_TRUE(Thrusters<S>::create(curved_layout<S>(S(12)), t).ok());
  // (12 / 16)^2 of the table's ends, the exponent 2 by default.
  for (Eigen::Index i = 0; i < 8; ++i) {
    EXPECT_NEAR(t.config().max_thrust(i), S(40 * 0.5625), tol<S>(40));
    EXPECT_NEAR(t.config().min_thrust(i), S(-32 * 0.5625), tol<S>(40));
  }
}

TYPED_TEST(ThrusterAllocationTest, InsideTheAttainableSetTheThrustersReproduceTau) {
  using S = TypeParam;
  for (const S voltage : {S(16), S(14.8)}) {
    Thrusters<S> t;
    ASSERT_TRUE(Thrusters<S>::create(curved_layout<S>(voltage), t).ok());
    const auto& curve = pwm_test_curve<S>();
    neurov_test::Rng rng(7);
    for (int k = 0; k < 200; ++k) {
      Vector6<S> tau;
      for (int i = 0; i < 6; ++i) tau(i) = rng.uniform<S>(-1, 1);
      // Small enough for every thruster: no saturation.
      tau.template head<3>() *= S(20);
      tau.template tail<3>() *= S(2);
      t.command(tau);
      ASSERT_TRUE((t.commanded().array() < t.config().max_thrust.array()).all()) << k;
      ASSERT_TRUE((t.commanded().array() > t.config().min_thrust.array()).all()) << k;
      t.advance(S(0.05));
      EXPECT_LT((t.wrench() - tau).norm(), tol<S>(40)) << k;
      // Each command gives its thrust on the table, interpolated here anew.
      for (Eigen::Index i = 0; i < 8; ++i) {
        const double c = static_cast<double>(t.actuator_commands()(i));
        int j = 0;
        while (j + 2 < curve.points && static_cast<double>(curve.command[j + 1]) < c) ++j;
        const double w = (c - curve.command[j]) / (curve.command[j + 1] - curve.command[j]);
        double f = curve.thrust[j] + w * (curve.thrust[j + 1] - curve.thrust[j]);
        if (std::abs(c - 1500) <= 40) f = 0;
        f *= std::pow(static_cast<double>(voltage) / 16, 2);
        EXPECT_NEAR(t.thrust()(i), f, tol<S>(40)) << k << " " << i;
        EXPECT_NEAR(t.thrust()(i), t.commanded()(i), tol<S>(40)) << k << " " << i;
      }
    }
  }
}

TYPED_TEST(ThrusterAllocationTest, OutsideTheAttainableSetTheWrenchKeepsItsDirection) {
  using S = TypeParam;
  Thrusters<S> t;
  ASSERT_TRUE(Thrusters<S>::create(curved_layout<S>(S(16)), t).ok());
  neurov_test::Rng rng(11);
  for (int k = 0; k < 200; ++k) {
    Vector6<S> tau;
    for (int i = 0; i < 6; ++i) tau(i) = rng.uniform<S>(-1, 1);
    tau *= S(2000);
    t.command(tau);
    t.advance(S(0.05));
    const Vector6<S> w = t.wrench();
    const S scale = w.dot(tau) / tau.squaredNorm();
    EXPECT_GT(scale, S(0)) << k;
    EXPECT_LT(scale, S(1)) << k;
    EXPECT_LT((w - scale * tau).norm(), tol<S>(2000)) << k;
    // Some thruster at its limit: the largest wrench along tau.
    const auto& u = t.thrust();
    const bool at_limit = ((u - t.config().max_thrust).cwiseAbs().array() < tol<S>(40)).any() ||
                          ((u - t.config().min_thrust).cwiseAbs().array() < tol<S>(40)).any();
    EXPECT_TRUE(at_limit) << k;
  }
}

TYPED_TEST(ThrusterAllocationTest, CurvesLagAndResetToNeutral) {
  using S = TypeParam;
  auto c = curved_layout<S>(S(16));
  for (auto& curve : c.curves) curve.time_constant = S(0.1);
  Thrusters<S> t;
  ASSERT_TRUE(Thrusters<S>::create(c, t).ok());
  Vector6<S> tau = Vector6<S>::Zero();
  tau(2) = S(40);
  t.command(tau);
  const auto target = t.commanded();
  t.advance(S(0.1));
  for (Eigen::Index i = 0; i < 8; ++i)
    EXPECT_NEAR(t.thrust()(i), target(i) * (1 - std::exp(-1.0)), tol<S>(40)) << i;
  t.reset();
  EXPECT_EQ(t.thrust().norm(), S(0));
  for (Eigen::Index i = 0; i < 8; ++i) EXPECT_EQ(t.actuator_commands()(i), S(1500));
}

TYPED_TEST(ThrusterAllocationTest, WithoutCurvesTheCommandIsTheThrust) {
  using S = TypeParam;
  auto c = curved_layout<S>(S(16));
  c.curves.clear();
  c.max_thrust = ThrusterConfig<S>::Vector::Constant(8, S(40));
  c.min_thrust = -c.max_thrust;
  Thrusters<S> t;
  ASSERT_TRUE(Thrusters<S>::create(c, t).ok());
  Vector6<S> tau;
  tau << S(10), S(-5), S(8), S(0.5), S(-0.3), S(1);
  t.command(tau);
  t.advance(S(0.05));
  EXPECT_EQ(t.actuator_commands(), t.commanded());
  EXPECT_LT((t.wrench() - tau).norm(), tol<S>(10));
}

TYPED_TEST(ThrusterAllocationTest, TheClosedLoopAppliesTheCurvesThrust) {
  using S = TypeParam;
  const Vehicle<S> vehicle(nerov_parameters<S>());
  SimulationConfig<S> c;
  c.duration = S(2);
  c.command.times.setZero(1);
  c.command.poses.setZero(1, 6);
  c.use_thrusters = true;
  c.thrusters = curved_layout<S>(S(16));
  Simulator<S> sim;
  const ValidationError e = Simulator<S>::create(vehicle, c, sim);
  ASSERT_TRUE(e.ok()) << e.field;
  Vector6<S> tau;
  tau << S(20), S(10), S(-30), S(1), S(-2), S(3);
  while (!sim.done()) ASSERT_EQ(sim.step(tau, ControllerReport<S>{}), Status::ok);
  const auto r = sim.result();
  for (Eigen::Index k = 0; k < r.steps; ++k)
    EXPECT_LT((r.tau_applied.row(k).transpose() - tau).norm(), tol<S>(40)) << k;
}

TYPED_TEST(ThrusterAllocationTest, BadCurveConfigurationsAreNamedErrors) {
  using S = TypeParam;
  Thrusters<S> t;
  const auto field = [&](const ThrusterConfig<S>& c) {
    const ValidationError e = Thrusters<S>::create(c, t);
    return e ? std::string(e.field) : std::string("valid");
  };
  auto c = curved_layout<S>(S(16));
  c.curves[3].thrust[7] = S(4);  // falls at 1700 us, outside the dead band
  EXPECT_EQ(field(c), "thruster_curve.thrust");
  c = curved_layout<S>(S(16));
  c.curves.pop_back();
  EXPECT_EQ(field(c), "thrusters.curves");
  c = curved_layout<S>(S(0));
  EXPECT_EQ(field(c), "thrusters.supply_voltage");
  c = curved_layout<S>(S(16));
  c.time_constant = S(0.1);
  EXPECT_EQ(field(c), "thrusters.time_constant");
  c = curved_layout<S>(S(16));
  c.max_thrust = ThrusterConfig<S>::Vector::Constant(8, S(41));
  c.min_thrust = -c.max_thrust;
  EXPECT_EQ(field(c), "thrusters.max_thrust");
  c.max_thrust.setConstant(S(30));
  EXPECT_EQ(field(c), "thrusters.min_thrust");
  c.min_thrust.setConstant(S(-30));
  EXPECT_EQ(field(c), "valid");
  EXPECT_EQ(t.config().max_thrust(0), S(30));
}

}  // namespace
