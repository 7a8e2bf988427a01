// The thruster curve: table interpolation with dead band and asymmetric
// thrust, voltage scaling, the inverse, lag and slew limit, bad input.
// The table is a test table (not manufacturer data): a curve with a jump-free
// dead band and reverse thrust about 0.8 of forward thrust, like a T200's.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "neurov/model/thruster_curve.hpp"
#include "curve_tables.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::pwm_test_curve;

template <typename S>
S tol(double scale) {
  return static_cast<S>(std::is_same<S, float>::value ? 1e-5 * scale : 1e-12 * scale);
}

NEUROV_SCALAR_SUITE(ThrusterCurveTest);

TYPED_TEST(ThrusterCurveTest, ReproducesTheTablePointsAndInterpolatesBetweenThem) {
  using S = TypeParam;
  ThrusterCurve<S> curve;
  ASSERT_TRUE(ThrusterCurve<S>::create(pwm_test_curve<S>(), curve).ok());
  const auto c = pwm_test_curve<S>();
  for (int i = 0; i < c.points; ++i)
    EXPECT_NEAR(curve.static_thrust(c.command[i], S(16)), c.thrust[i], tol<S>(40)) << i;
  // Midway between 1700 (15 N) and 1800 (27 N), a quarter of the way between
  // 1200 (-22 N) and 1300 (-12 N).
  EXPECT_NEAR(curve.static_thrust(S(1750), S(16)), S(21), tol<S>(40));
  EXPECT_NEAR(curve.static_thrust(S(1225), S(16)), S(-19.5), tol<S>(40));
  // Dead band, and saturation at the table's ends.
  EXPECT_EQ(curve.static_thrust(S(1530), S(16)), S(0));
  EXPECT_EQ(curve.static_thrust(S(1470), S(16)), S(0));
  EXPECT_EQ(curve.static_thrust(S(2500), S(16)), S(40));
  EXPECT_EQ(curve.static_thrust(S(900), S(16)), S(-32));
  // Asymmetric: full reverse is weaker than full forward.
  EXPECT_LT(-curve.min_thrust(S(16)), curve.max_thrust(S(16)));
}

TYPED_TEST(ThrusterCurveTest, ThrustScalesWithTheVoltageSquaredByDefault) {
  using S = TypeParam;
  ThrusterCurve<S> curve;
  ASSERT_TRUE(ThrusterCurve<S>::create(pwm_test_curve<S>(), curve).ok());
  EXPECT_NEAR(curve.static_thrust(S(1900), S(12)), S(40) * S(0.5625), tol<S>(40));
  EXPECT_NEAR(curve.max_thrust(S(8)), S(10), tol<S>(40));
  EXPECT_EQ(curve.static_thrust(S(1900), S(0)), S(0));
}

TYPED_TEST(ThrusterCurveTest, InverseReturnsTheCommandOfEveryAttainableThrust) {
  using S = TypeParam;
  ThrusterCurve<S> curve;
  ASSERT_TRUE(ThrusterCurve<S>::create(pwm_test_curve<S>(), curve).ok());
  for (const double v : {16.0, 14.8}) {
    const S volts = static_cast<S>(v);
    for (int k = -100; k <= 100; ++k) {
      const S t = static_cast<S>(k) / S(100) *
                  (k < 0 ? -curve.min_thrust(volts) : curve.max_thrust(volts));
      const S cmd = curve.command_for(t, volts);
      EXPECT_NEAR(curve.static_thrust(cmd, volts), t, tol<S>(40)) << "k=" << k << " V=" << v;
    }
  }
  // Known points: 21 N is 1750 us; -4 N is 1400 us; 0 N is neutral.
  EXPECT_NEAR(curve.command_for(S(21), S(16)), S(1750), tol<S>(2000));
  EXPECT_NEAR(curve.command_for(S(-4), S(16)), S(1400), tol<S>(2000));
  EXPECT_EQ(curve.command_for(S(0), S(16)), S(1500));
  // Beyond the attainable: the end commands.
  EXPECT_EQ(curve.command_for(S(100), S(16)), S(1900));
  EXPECT_EQ(curve.command_for(S(-100), S(16)), S(1100));
}

TYPED_TEST(ThrusterCurveTest, InverseOfACurveThatJumpsAtTheDeadBandGivesItsEdge) {
  using S = TypeParam;
  auto c = pwm_test_curve<S>();
  c.dead_band = S(80);  // edges 1420 and 1580, where the table is -2.667 N and 3.333 N
  ThrusterCurve<S> curve;
  ASSERT_TRUE(ThrusterCurve<S>::create(c, curve).ok());
  EXPECT_EQ(curve.command_for(S(1), S(16)), S(1580));
  EXPECT_EQ(curve.command_for(S(-1), S(16)), S(1420));
  EXPECT_NEAR(curve.command_for(S(5), S(16)), S(1600), tol<S>(2000));
}

TYPED_TEST(ThrusterCurveTest, LagIsTheExactFirstOrderResponseAndTheSlewLimitHolds) {
  using S = TypeParam;
  auto c = pwm_test_curve<S>();
  c.time_constant = S(0.1);
  ThrusterCurve<S> curve;
  ASSERT_TRUE(ThrusterCurve<S>::create(c, curve).ok());
  for (int k = 1; k <= 20; ++k) {
    ASSERT_EQ(curve.step(S(1900), S(16), S(0.01)), Status::ok);
    EXPECT_NEAR(curve.thrust(), S(40) * (S(1) - std::exp(-S(0.01) * S(k) / S(0.1))), tol<S>(40));
  }
  c.time_constant = S(0);
  c.slew_rate = S(100);  // N/s
  ASSERT_TRUE(ThrusterCurve<S>::create(c, curve).ok());
  for (int k = 1; k <= 50; ++k) {
    ASSERT_EQ(curve.step(S(1900), S(16), S(0.01)), Status::ok);
    EXPECT_NEAR(curve.thrust(), std::fmin(S(40), S(k)), tol<S>(40)) << k;
  }
  // Reversal is limited too.
  ASSERT_EQ(curve.step(S(1100), S(16), S(0.01)), Status::ok);
  EXPECT_NEAR(curve.thrust(), S(39), tol<S>(40));
}

TYPED_TEST(ThrusterCurveTest, ARejectedStepLeavesTheThrustAsItWas) {
  using S = TypeParam;
  ThrusterCurve<S> curve;
  ASSERT_TRUE(ThrusterCurve<S>::create(pwm_test_curve<S>(), curve).ok());
  ASSERT_EQ(curve.step(S(1700), S(16), S(0.01)), Status::ok);
  EXPECT_EQ(curve.step(std::nan(""), S(16), S(0.01)), Status::non_finite_input);
  EXPECT_EQ(curve.step(S(1700), S(16), S(-1)), Status::invalid_argument);
  EXPECT_EQ(curve.thrust(), S(15));
  ThrusterCurve<S> empty;
  EXPECT_EQ(empty.step(S(1700), S(16), S(0.01)), Status::invalid_argument);
}

TYPED_TEST(ThrusterCurveTest, BadCurvesAreNamedErrors) {
  using S = TypeParam;
  ThrusterCurve<S> curve;
  const auto field = [&](const ThrusterCurveConfig<S>& c) {
    const ValidationError e = ThrusterCurve<S>::create(c, curve);
    return std::string(e.ok() ? "ok" : e.field) + "[" + std::to_string(e.index) + "]";
  };
  auto c = pwm_test_curve<S>();
  c.thrust[7] = S(4);  // falls from 5 N at 1600 us: not monotonic outside the dead band
  EXPECT_EQ(field(c), "thruster_curve.thrust[7]");
  c = pwm_test_curve<S>();
  c.thrust[2] = S(-23);  // -22 then -23: falls on the reverse side
  EXPECT_EQ(field(c), "thruster_curve.thrust[2]");
  c = pwm_test_curve<S>();
  c.thrust[4] = S(0.5);  // positive below the dead band
  EXPECT_EQ(field(c), "thruster_curve.thrust[-1]");
  c = pwm_test_curve<S>();
  c.thrust[5] = S(-0.5);  // negative above the dead band
  EXPECT_EQ(field(c), "thruster_curve.thrust[-1]");
  c = pwm_test_curve<S>();
  c.command[3] = S(1300);
  EXPECT_EQ(field(c), "thruster_curve.command[3]");
  c = pwm_test_curve<S>();
  c.points = 1;
  EXPECT_EQ(field(c), "thruster_curve.points[-1]");
  c = pwm_test_curve<S>();
  c.slew_rate = S(-1);
  EXPECT_EQ(field(c), "thruster_curve.slew_rate[-1]");
  c = pwm_test_curve<S>();
  c.time_constant = S(-0.1);
  EXPECT_EQ(field(c), "thruster_curve.time_constant[-1]");
  c = pwm_test_curve<S>();
  c.dead_band = S(-1);
  EXPECT_EQ(field(c), "thruster_curve.dead_band[-1]");
  c = pwm_test_curve<S>();
  c.reference_voltage = S(0);
  EXPECT_EQ(field(c), "thruster_curve.reference_voltage[-1]");
  c = pwm_test_curve<S>();
  c.neutral = S(2000);
  EXPECT_EQ(field(c), "thruster_curve.neutral[-1]");
  // Flat inside the dead band is fine (the zero rows of a measured table).
  c = pwm_test_curve<S>();
  EXPECT_EQ(field(c), "ok[-1]");
}

}  // namespace
