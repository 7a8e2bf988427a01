// The Simulator allocates in create() only: step() and reset() touch no heap,
// whatever the run holds (noise, every sensor fault, thrusters with failures,
// current steps, disturbances, a control delay, logged parameters, refused steps), in float
// and double.
//
// The detectors are in alloc_probe.hpp; the counting global operator new is
// defined in alloc_foundation.cpp (there may be only one per executable).
#include "alloc_probe.hpp"
#include "alloc_closed_loop.hpp"


#include <gtest/gtest.h>

#include "neurov/neurov.hpp"
#include "curve_tables.hpp"
#include "sensor_suite.hpp"

namespace {

using namespace neurov;

using alloc_probe::expect_run_does_not_allocate;

NEUROV_SCALAR_SUITE(SimulatorAllocTest);

template <typename S>
SimulationConfig<S> busy_config(RefusedStepPolicy policy) {
  SimulationConfig<S> c;
  c.duration = S(30);
  c.command.times.resize(3);
  c.command.times << S(0), S(10), S(20);
  c.command.poses.setZero(3, 6);
  c.command.poses.row(1) << S(3), S(0), S(1), S(0), S(0), S(0.5);
  c.command.poses.row(2) << S(3), S(3), S(1), S(0), S(0), S(1.5);
  c.noise_eta.setConstant(S(0.01));
  c.noise_nu.setConstant(S(0.005));
  c.refused_step_policy = policy;
  using neurov_test::sensor_fault;
  SensorFault<S> burst = sensor_fault<S>(SensorFaultKind::noise_burst, 8, 10);
  burst.noise_eta.setConstant(S(0.1));
  c.sensor_faults = {sensor_fault<S>(SensorFaultKind::freeze, 2, 4),
                     sensor_fault<S>(SensorFaultKind::dropout, 6, 7), burst};
  CurrentStep<S> step;
  step.time = S(12);
  step.velocity << S(0.2), S(0), S(0);
  c.current_steps = {step};
  c.current_amplitude << S(0.05), S(0), S(0);
  c.current_period = S(10);
  SinusoidalDisturbance<S> d;
  d.amplitude = S(5);
  d.frequency = S(0.1);
  c.disturbances = {d};
  c.use_thrusters = true;
  const double dir[6][3] = {{1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  const double pos[6][3] = {{-0.5, 0.3, 0}, {-0.5, -0.3, 0}, {0.4, 0, 0},
                            {0.4, 0, 0},    {-0.4, 0.3, 0},  {-0.4, -0.3, 0}};
  c.thrusters.matrix.resize(6, 6);
  for (int j = 0; j < 6; ++j) {
    const Eigen::Vector3d r(pos[j][0], pos[j][1], pos[j][2]), u(dir[j][0], dir[j][1], dir[j][2]);
    c.thrusters.matrix.col(j) << u.cast<S>(), r.cross(u).cast<S>();
  }
  c.thrusters.max_thrust = ThrusterConfig<S>::Vector::Constant(6, S(100));
  c.thrusters.min_thrust = -c.thrusters.max_thrust;
  c.thrusters.time_constant = S(0.2);
  ThrusterFailure<S> f;
  f.index = 1;
  f.efficiency = S(0.5);
  f.time = S(15);
  c.thruster_failures = {f};
  c.control_delay = 2;  // the pending forces' ring
  return c;
}

/// busy_config with the four sensors and the EKF in place of the white noise.
template <typename S>
SimulationConfig<S> sensed_config(RefusedStepPolicy policy, EstimatorType estimator) {
  SimulationConfig<S> c = busy_config<S>(policy);
  c.noise_eta.setZero();
  c.noise_nu.setZero();
  c.sensors = neurov_test::sensor_suite<S>();
  c.estimator.type = estimator;
  return c;
}

/// busy_config with a PWM curve per thruster: a dead band, asymmetric
/// thrust, lag and slew limit.
template <typename S>
SimulationConfig<S> curved_config(RefusedStepPolicy policy) {
  SimulationConfig<S> config = busy_config<S>(policy);
  const double pwm[] = {1100, 1300, 1460, 1540, 1700, 1900};
  const double thrust[] = {-80, -30, 0, 0, 40, 100};
  ThrusterCurveConfig<S> curve = neurov_test::curve_table<S>(pwm, thrust);
  curve.neutral = S(1500);
  curve.dead_band = S(40);
  curve.reference_voltage = S(16);
  curve.time_constant = S(0.1);
  curve.slew_rate = S(500);
  config.thrusters.curves.assign(6, curve);
  config.thrusters.supply_voltage = S(15);
  config.thrusters.time_constant = S(0);
  config.thrusters.min_thrust.resize(0);
  config.thrusters.max_thrust.resize(0);
  return config;
}

/// Every configuration here has a sensor dropout: 1 s at 5 Hz, in each of the
/// two runs, refused by the controller.
constexpr long kDropoutRefusals = 2 * 5;

/// The PD gains of the runs below (the controller is not what they test).
template <typename S>
PDConfig<S> pd_gains() {
  PDConfig<S> cfg;
  cfg.kp.setConstant(S(50));
  cfg.kd.setConstant(S(80));
  return cfg;
}

TYPED_TEST(SimulatorAllocTest, StepAndResetDoNotAllocateWithAPDController) {
  using S = TypeParam;
  PDController<S> pd;
  ASSERT_TRUE(PDController<S>::create(pd_gains<S>(), pd).ok());
  expect_run_does_not_allocate<S>(pd, busy_config<S>(RefusedStepPolicy::zero), kDropoutRefusals);
  expect_run_does_not_allocate<S>(pd, busy_config<S>(RefusedStepPolicy::hold), kDropoutRefusals);
}

TYPED_TEST(SimulatorAllocTest, StepAndResetDoNotAllocateWithThrusterCurves) {
  using S = TypeParam;
  PDController<S> pd;
  ASSERT_TRUE(PDController<S>::create(pd_gains<S>(), pd).ok());
  const SimulationConfig<S> c = curved_config<S>(RefusedStepPolicy::hold);
  expect_run_does_not_allocate<S>(pd, c, kDropoutRefusals);
}

TYPED_TEST(SimulatorAllocTest, StepAndResetDoNotAllocateWithSensorsAndAnEstimator) {
  using S = TypeParam;
  PDController<S> pd;
  ASSERT_TRUE(PDController<S>::create(pd_gains<S>(), pd).ok());
  for (EstimatorType e : {EstimatorType::none, EstimatorType::ekf}) {
    const SimulationConfig<S> c = sensed_config<S>(RefusedStepPolicy::hold, e);
    expect_run_does_not_allocate<S>(pd, c, kDropoutRefusals);
  }
}

TYPED_TEST(SimulatorAllocTest, StepAndResetDoNotAllocateWhileLoggingParameters) {
  using S = TypeParam;
  LinearAdaptiveConfig<S> cfg;
  cfg.kd.setConstant(S(50));
  ASSERT_TRUE(regressor_parameters(nerov_parameters<S>(), cfg.theta0).ok());
  LinearAdaptiveController<S> linear;
  ASSERT_TRUE(LinearAdaptiveController<S>::create(cfg, linear).ok());
  expect_run_does_not_allocate<S>(linear, busy_config<S>(RefusedStepPolicy::hold),
                                  kDropoutRefusals);
}

}  // namespace
