// A vehicle's sensor suite as the tests run it (an AHRS with its gyro, a DVL
// that drops 10 % of its samples, a depth sensor and an acoustic fix 0.5 s
// old), the noise figures the EKF is told for such a suite, and faults of
// the sensed state.
#pragma once

#include "neurov/estimation/ekf.hpp"
#include "neurov/sim/config.hpp"
#include "neurov/sim/sensing.hpp"

namespace neurov_test {

template <typename S>
neurov::SensorsConfig<S> sensor_suite() {
  neurov::SensorsConfig<S> s;
  s.imu.emplace();
  s.imu->attitude_noise = S(0.005);
  s.imu->gyro_noise = S(0.001);
  s.imu->gyro_bias_walk = S(1e-5);
  s.dvl.emplace();
  s.dvl->noise = S(0.01);
  s.dvl->dropout_rate = 0.1;
  s.depth.emplace();
  s.depth->noise = S(0.02);
  s.usbl.emplace();
  s.usbl->noise = S(0.5);
  s.usbl->latency = 0.5;
  return s;
}

/// The process noise and the measurement noise of the suite's sensors; the
/// initial spread (initial_std) is left to the caller.
template <typename S>
neurov::EkfConfig<S> ekf_noise() {
  neurov::EkfConfig<S> c;
  c.linear_acceleration_noise = S(0.02);
  c.angular_acceleration_noise = S(0.002);
  c.gyro_bias_walk = S(1e-4);
  c.attitude_noise = S(0.005);
  c.gyro_noise = S(0.001);
  c.dvl_noise = S(0.01);
  c.depth_noise = S(0.02);
  c.position_noise = S(0.5);
  return c;
}

/// A fault of the sensed state from start to end [s].
template <typename S>
neurov::SensorFault<S> sensor_fault(neurov::SensorFaultKind kind, double start, double end) {
  neurov::SensorFault<S> f;
  f.kind = kind;
  f.start = S(start);
  f.end = S(end);
  return f;
}

}  // namespace neurov_test
