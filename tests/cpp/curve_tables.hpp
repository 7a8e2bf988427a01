// Thruster curve tables for the tests: test data, not a manufacturer's. No
// GoogleTest here, so the no-exceptions firmware test can use them too.
#pragma once

#include "neurov/model/thruster_curve.hpp"

namespace neurov_test {

/// The N (command, thrust) rows into a curve's table; every other field of the
/// curve at its default.
template <typename S, int N>
neurov::ThrusterCurveConfig<S> curve_table(const double (&command)[N], const double (&thrust)[N]) {
  neurov::ThrusterCurveConfig<S> c;
  c.points = N;
  for (int i = 0; i < N; ++i) {
    c.command[i] = static_cast<S>(command[i]);
    c.thrust[i] = static_cast<S>(thrust[i]);
  }
  return c;
}

/// PWM [us] -> thrust [N] at 16 V: reverse about 0.8 of forward, zero from
/// 1460 to 1540 us (a dead band of 40 us about 1500).
template <typename S>
neurov::ThrusterCurveConfig<S> pwm_test_curve() {
  const double pwm[] = {1100, 1200, 1300, 1400, 1460, 1540, 1600, 1700, 1800, 1900};
  const double thrust[] = {-32, -22, -12, -4, 0, 0, 5, 15, 27, 40};
  neurov::ThrusterCurveConfig<S> c = curve_table<S>(pwm, thrust);
  c.neutral = S(1500);
  c.dead_band = S(40);
  c.reference_voltage = S(16);
  return c;
}

/// A normalised command in [-1, 1] with a dead band of 0.1 about 0 and
/// `reverse` N at -1, `forward` N at +1, at 16 V.
template <typename S>
neurov::ThrusterCurveConfig<S> unit_test_curve(double reverse, double forward) {
  const double command[] = {-1, -0.1, 0.1, 1};
  const double thrust[] = {reverse, 0, 0, forward};
  neurov::ThrusterCurveConfig<S> c = curve_table<S>(command, thrust);
  c.dead_band = S(0.1);
  c.reference_voltage = S(16);
  return c;
}

}  // namespace neurov_test
