// The ArduSub controller stage by stage against values worked by hand from
// the documented definitions (docs/ardusub.md), the motor mixing against the
// frames' published motor layout, and its refusals.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "neurov/neurov.hpp"

namespace {

using namespace neurov;
using namespace neurov::ardusub;
using V6 = Vector6<double>;

TEST(ArduSubStages, SquareRootControllerIsLinearThenConstantDeceleration) {
  // P = 2, a = 4: linear up to a / P^2 = 1.
  EXPECT_DOUBLE_EQ(sqrt_controller(0.5, 2.0, 4.0, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(sqrt_controller(3.0, 2.0, 4.0, 0.0), std::sqrt(2.0 * 4.0 * (3.0 - 0.5)));
  EXPECT_DOUBLE_EQ(sqrt_controller(-3.0, 2.0, 4.0, 0.0), -std::sqrt(20.0));
  // Never more than the whole error in one step: |e| / dt = 3.
  EXPECT_DOUBLE_EQ(sqrt_controller(3.0, 2.0, 4.0, 1.0), 3.0);
  // No acceleration limit: P alone.
  EXPECT_DOUBLE_EQ(sqrt_controller(3.0, 2.0, 0.0, 0.0), 6.0);
}

TEST(ArduSubStages, LowPassAndShaping) {
  // 10 Hz at 100 Hz: RC = 1 / (20 pi), alpha = 0.01 / (0.01 + RC).
  EXPECT_NEAR(low_pass_alpha(10.0, 0.01), 0.01 / (0.01 + 1.0 / (20.0 * M_PI)), 1e-15);
  EXPECT_DOUBLE_EQ(low_pass_alpha(0.0, 0.01), 1.0);  // 0 Hz: off
  EXPECT_DOUBLE_EQ(shape_rate(0.0, 5.0, 10.0, 0.1), 1.0);  // at most a dt
  EXPECT_DOUBLE_EQ(shape_rate(0.0, 0.5, 10.0, 0.1), 0.5);
}

TEST(ArduSubStages, RatePidTermsByHand) {
  const PidGains<double> g{0.135, 0.09, 0.01, 0.1, 0.444, 0.0, 0.0, 0.0};
  RatePid<double> pid;
  const double dt = 0.0025;
  // First sample: error 1, no derivative, I = 1 * 0.09 * dt.
  EXPECT_NEAR(pid.update(g, 1.0, 0.0, dt, false), 0.135 + 0.000225 + 0.1, 1e-15);
  // Second: error 0.5, derivative (0.5 - 1) / dt = -200.
  EXPECT_NEAR(pid.update(g, 1.0, 0.5, dt, false), 0.0675 + 0.0003375 - 2.0 + 0.1, 1e-12);
  // Saturated in the error's direction: the integrator holds.
  const double held = pid.integrator;
  pid.update(g, 1.0, 0.5, dt, true);
  EXPECT_DOUBLE_EQ(pid.integrator, held);
  // IMAX.
  const PidGains<double> big{0.0, 1000.0, 0.0, 0.0, 0.444, 0.0, 0.0, 0.0};
  RatePid<double> wind;
  for (int i = 0; i < 10; ++i) wind.update(big, 1.0, 0.0, dt, false);
  EXPECT_DOUBLE_EQ(wind.integrator, 0.444);
  // A 10 Hz error filter: the error moves by alpha of the step.
  const PidGains<double> fe{1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 10.0, 0.0};
  RatePid<double> f;
  f.update(fe, 0.0, 0.0, dt, false);
  EXPECT_NEAR(f.update(fe, 1.0, 0.0, dt, false), low_pass_alpha(10.0, dt), 1e-15);
}

TEST(ArduSubMotors, PureCommandsLightTheDocumentedThrusters) {
  const auto f = frame_factors<double>(2);
  MotorVector<double> out;
  const auto light = [&](int axis) {
    V6 in = V6::Zero();
    in(axis) = 0.5;
    mix(f, 8, in, out);
    return out;
  };
  MotorVector<double> e;
  e << 0, 0, 0, 0, -0.5, -0.5, -0.5, -0.5;  // up: vertical thrusters reverse (push up)
  EXPECT_EQ(light(throttle), e);
  e << -0.5, -0.5, 0.5, 0.5, 0, 0, 0, 0;
  EXPECT_EQ(light(forward), e);
  e << 0.5, -0.5, 0.5, -0.5, 0, 0, 0, 0;
  EXPECT_EQ(light(lateral), e);
  e << 0.5, -0.5, -0.5, 0.5, 0, 0, 0, 0;
  EXPECT_EQ(light(yaw), e);
  e << 0, 0, 0, 0, 0.5, -0.5, 0.5, -0.5;
  EXPECT_EQ(light(roll), e);
  e << 0, 0, 0, 0, -0.5, -0.5, 0.5, 0.5;
  EXPECT_EQ(light(pitch), e);
  // The vectored frame: two vertical motors, no pitch.
  const auto f1 = frame_factors<double>(1);
  V6 in = V6::Zero();
  in(roll) = 0.5;
  mix(f1, 6, in, out);
  e << 0, 0, 0, 0, 0.5, -0.5, 0, 0;
  EXPECT_EQ(out, e);
}

TEST(ArduSubMotors, FactorsAgreeWithTheThrusterGeometry) {
  for (int frame : {1, 2}) {
    const auto f = frame_factors<double>(frame);
    const auto b = frame_wrench_matrix<double>(frame);
    // Axis -> wrench row and sign: roll Mx, pitch My, yaw Mz, throttle -Fz, forward Fx, lateral Fy.
    const int row[6] = {3, 4, 5, 2, 0, 1};
    const double sign[6] = {1, 1, 1, -1, 1, 1};
    for (int a = 0; a < 6; ++a)
      for (int i = 0; i < frame_motors(frame); ++i) {
        if (f(a, i) == 0.0) continue;
        EXPECT_GT(f(a, i) * sign[a] * b(row[a], i), 0.0)
            << "frame " << frame << " axis " << a << " motor " << i + 1;
      }
  }
}

TEST(ArduSubMotors, GroupsScaleTogetherAndDirectionReversesThePwm) {
  const auto f = frame_factors<double>(2);
  V6 in = V6::Zero();
  in(forward) = 1.0;
  in(yaw) = 1.0;  // motor 2: -1 - 1 = -2, the horizontal group halves
  MotorVector<double> out;
  const MixLimits lim = mix(f, 8, in, out);
  EXPECT_TRUE(lim.horizontal);
  EXPECT_FALSE(lim.vertical);
  EXPECT_DOUBLE_EQ(out(1), -1.0);
  EXPECT_DOUBLE_EQ(out(0), 0.0);
  EXPECT_DOUBLE_EQ(out(2), 0.0);
  EXPECT_DOUBLE_EQ(out(3), 1.0);
  EXPECT_DOUBLE_EQ(motor_pwm(0.5, 1.0, 1100.0, 1900.0), 1700.0);
  EXPECT_DOUBLE_EQ(motor_pwm(0.5, -1.0, 1100.0, 1900.0), 1300.0);
  EXPECT_DOUBLE_EQ(motor_pwm(1.0, 1.0, 1100.0, 1800.0), 1800.0);  // MOT_PWM_MAX
}

TEST(ArduSubController, DepthHoldFirstIterationByHand) {
  ArduSubConfig<double> c;
  c.FRAME_CONFIG = 2;
  c.mode = 1;
  c.dt = 0.0025;  // one iteration
  ArduSubController<double> ctl(c);
  V6 eta_d = V6::Zero();
  eta_d(2) = 1.0;  // 1 m deeper
  V6 tau;
  ASSERT_EQ(ctl.step(V6::Zero(), V6::Zero(), eta_d, V6::Zero(), V6::Zero(), tau), Status::ok);
  // Depth error -100 cm: sqrt controller (P 3, a 100) -137.4 cm/s, held at
  // -PILOT_SPEED_DN = -50; VELZ_P 8: -400 cm/s/s; ACCZ P 0.5 and I 0.1 dt:
  // -200 - 0.1; x 0.002: throttle -0.4002 (down).
  EXPECT_NEAR(ctl.axis_inputs()(throttle), -0.4002, 1e-12);
  for (int i = 4; i < 8; ++i) EXPECT_NEAR(ctl.pwm()(i), 1500 + 400 * 0.4002, 1e-9);
  for (int i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(ctl.pwm()(i), 1500);
  EXPECT_GT(tau(2), 0.0);  // pushes down
  EXPECT_NEAR(tau(0), 0.0, 1e-12);
  // PSC_ACCZ_FF adds FF x the acceleration target: 0.1 x -400 x 0.002 = -0.08.
  c.PSC_ACCZ_FF = 0.1;
  ArduSubController<double> ff(c);
  ASSERT_EQ(ff.step(V6::Zero(), V6::Zero(), eta_d, V6::Zero(), V6::Zero(), tau), Status::ok);
  EXPECT_NEAR(ff.axis_inputs()(throttle), -0.4802, 1e-12);
}

TEST(ArduSubController, TheMotorStageAloneIsTheLoopsOwn) {
  // mix_pwm (the replay of a log's inputs) gives the PWMs a step's mixer
  // inputs gave, with a reversed motor; and changes nothing.
  ArduSubConfig<double> c;
  c.FRAME_CONFIG = 2;
  c.mode = 2;
  c.dt = 0.0025;
  c.MOT_3_DIRECTION = -1;
  ArduSubController<double> ctl(c);
  V6 eta, nu, eta_d, tau;
  eta << 0.3, -0.2, 1.1, 0.05, -0.02, 0.4;
  nu << 0.1, 0.0, -0.05, 0.01, 0.02, -0.03;
  eta_d << 1.0, 0.5, 2.0, 0.0, 0.0, 0.2;
  ASSERT_EQ(ctl.step(eta, nu, eta_d, V6::Zero(), V6::Zero(), tau), Status::ok);
  const auto state = ctl.state();
  const auto pwm = ctl.mix_pwm(ctl.axis_inputs());
  for (int i = 0; i < 8; ++i) EXPECT_DOUBLE_EQ(pwm(i), ctl.pwm()(i)) << i;
  EXPECT_EQ(ctl.state(), state);
  V6 forward = V6::Zero();
  forward(ardusub::forward) = 2.0;  // held at 1
  EXPECT_DOUBLE_EQ(ctl.mix_pwm(forward)(2), 1500 - 400);
}

TEST(ArduSubController, AtRestOnTargetGivesNoWrench) {
  ArduSubConfig<float> c;
  c.FRAME_CONFIG = 2;
  c.mode = 2;
  c.dt = 0.2f;
  ArduSubController<float> ctl(c);
  Vector6<float> tau;
  const Vector6<float> z = Vector6<float>::Zero();
  ASSERT_EQ(ctl.step(z, z, z, z, z, tau), Status::ok);
  EXPECT_EQ(tau, z);
}

TEST(ArduSubController, ARestoredSnapshotStepsAsTheOriginal) {
  ArduSubConfig<double> c;
  c.FRAME_CONFIG = 2;
  c.mode = 2;
  c.dt = 0.2;
  ArduSubController<double> a(c), b(c);
  V6 eta, nu, eta_d, tau_a, tau_b;
  eta << 0.3, -0.2, 1.1, 0.05, -0.02, 0.4;
  nu << 0.1, 0.0, -0.05, 0.01, 0.02, -0.03;
  eta_d << 1.0, 0.5, 2.0, 0.0, 0.0, 0.2;
  for (int k = 0; k < 3; ++k) ASSERT_EQ(a.step(eta, nu, eta_d, V6::Zero(), V6::Zero(), tau_a), Status::ok);
  ASSERT_TRUE(b.restore(a.tracking(), a.last_status(), a.state()));
  EXPECT_EQ(b.state(), a.state());
  eta(0) += 0.1;
  ASSERT_EQ(a.step(eta, nu, eta_d, V6::Zero(), V6::Zero(), tau_a), Status::ok);
  ASSERT_EQ(b.step(eta, nu, eta_d, V6::Zero(), V6::Zero(), tau_b), Status::ok);
  EXPECT_EQ(tau_a, tau_b);
  auto bad = a.state();
  bad(0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(b.restore(a.tracking(), a.last_status(), bad));
  EXPECT_EQ(b.state(), a.state());
}

TEST(ArduSubController, AnOverflowIsRefusedAndLeavesTheStateAsItWas) {
  ArduSubConfig<double> c;
  c.FRAME_CONFIG = 2;
  c.mode = 2;
  ArduSubController<double> ctl(c);
  V6 tau;
  ASSERT_EQ(ctl.step(V6::Zero(), V6::Zero(), V6::Zero(), V6::Zero(), V6::Zero(), tau), Status::ok);
  const auto before = ctl.state();
  V6 far = V6::Zero();
  far(0) = 1e306;  // x100 in centimetres overflows
  far(1) = 1e306;
  const Status st = ctl.step(V6::Zero(), V6::Zero(), far, V6::Zero(), V6::Zero(), tau);
  if (st == Status::ok) {
    EXPECT_TRUE(tau.allFinite());
    EXPECT_TRUE(ctl.state().allFinite());
  } else {
    EXPECT_EQ(st, Status::non_finite_output);
    EXPECT_EQ(tau, V6::Zero());
    EXPECT_EQ(ctl.state(), before);
  }
}

TEST(ArduSubController, BadConfigurationsAreNamed) {
  ArduSubConfig<double> c;
  c.ATC_RAT_RLL_P = -0.1;
  EXPECT_STREQ(validate(c).field, "ATC_RAT_RLL_P");
  c = ArduSubConfig<double>{};
  c.PSC_ACCZ_I = std::numeric_limits<double>::quiet_NaN();
  EXPECT_STREQ(validate(c).field, "PSC_ACCZ_I");
  c = ArduSubConfig<double>{};
  c.FRAME_CONFIG = 0;
  EXPECT_STREQ(validate(c).field, "FRAME_CONFIG");
  c = ArduSubConfig<double>{};
  c.MOT_3_DIRECTION = 0.5;
  EXPECT_STREQ(validate(c).field, "MOT_3_DIRECTION");
  c = ArduSubConfig<double>{};
  c.PSC_VELZ_IMAX = 5000;  // out of the documented range, but ArduSub flies it
  EXPECT_TRUE(validate(c).ok());
}

}  // namespace
