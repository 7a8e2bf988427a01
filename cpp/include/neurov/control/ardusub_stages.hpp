// The building blocks of ArduSub's controllers, each as ArduPilot's
// documentation describes it (docs/ardusub.md names the page of each):
//
// - low_pass_alpha: the first-order low-pass of a PID's filters (FLTT,
//   FLTE, FLTD): y += alpha (x - y), alpha = dt / (dt + 1 / (2 pi f)); a
//   cut-off of 0 Hz turns the filter off (alpha = 1).
// - sqrt_controller: a P controller whose correction, beyond the distance
//   where P alone would ask for more than the acceleration limit a, follows
//   the constant-deceleration curve sqrt(2 a (|e| - a / (2 P^2))) instead of
//   P e, and never asks for more than the whole error in one step (|e| / dt).
//   With a <= 0 it is P e.
// - shape_rate: a rate moved toward its target by at most a dt per step (the
//   input shaping's acceleration limit).
// - RatePid: ArduPilot's PID as its parameter reference defines the terms:
//   target filtered at FLTT, error at FLTE, derivative of the filtered error
//   at FLTD; P e + I + D + FF target, the integrator limited to +-IMAX and
//   held while the output is saturated in the error's direction.
#pragma once

#include <algorithm>
#include <cmath>

namespace neurov::ardusub {

template <typename Scalar>
Scalar low_pass_alpha(Scalar cutoff_hz, Scalar dt) noexcept {
  if (!(cutoff_hz > Scalar(0))) return Scalar(1);
  const Scalar rc = Scalar(1) / (Scalar(2) * Scalar(3.14159265358979323846) * cutoff_hz);
  return dt / (dt + rc);
}

template <typename Scalar>
Scalar sqrt_controller(Scalar error, Scalar p, Scalar accel_limit, Scalar dt) noexcept {
  Scalar correction;
  if (!(accel_limit > Scalar(0))) {
    correction = error * p;
  } else if (!(p > Scalar(0))) {
    // No P: the constant-deceleration curve alone.
    const Scalar mag = std::sqrt(Scalar(2) * accel_limit * std::abs(error));
    correction = error > Scalar(0) ? mag : -mag;
  } else {
    const Scalar linear = accel_limit / (p * p);
    if (error > linear)
      correction = std::sqrt(Scalar(2) * accel_limit * (error - linear / Scalar(2)));
    else if (error < -linear)
      correction = -std::sqrt(Scalar(2) * accel_limit * (-error - linear / Scalar(2)));
    else
      correction = error * p;
  }
  if (dt > Scalar(0)) {
    const Scalar most = std::abs(error) / dt;
    correction = std::max(-most, std::min(most, correction));
  }
  return correction;
}

template <typename Scalar>
Scalar shape_rate(Scalar rate, Scalar target, Scalar accel_limit, Scalar dt) noexcept {
  if (!(accel_limit > Scalar(0))) return target;
  const Scalar step = accel_limit * dt;
  return rate + std::max(-step, std::min(step, target - rate));
}

/// One PID's gains and filters (ArduPilot's P, I, D, FF, IMAX, FLTT, FLTE,
/// FLTD), in the units of the loop it closes.
template <typename Scalar>
struct PidGains {
  Scalar p, i, d, ff, imax, fltt, flte, fltd;
};

/// One PID's memory: the filtered target, error and derivative, the
/// integrator, and whether the filters have a first sample.
template <typename Scalar>
struct RatePid {
  Scalar target = Scalar(0);
  Scalar error = Scalar(0);
  Scalar derivative = Scalar(0);
  Scalar integrator = Scalar(0);
  bool started = false;

  void reset() noexcept { *this = RatePid{}; }

  /// The output for this target and measurement; `limited` says the output
  /// stage saturated last step (the integrator then moves only inward).
  Scalar update(const PidGains<Scalar>& g, Scalar target_in, Scalar measurement, Scalar dt,
                bool limited) noexcept {
    if (!started) {
      target = target_in;
      error = target_in - measurement;
      derivative = Scalar(0);
      started = true;
    } else {
      target += low_pass_alpha(g.fltt, dt) * (target_in - target);
      const Scalar error_last = error;
      error += low_pass_alpha(g.flte, dt) * ((target - measurement) - error);
      const Scalar raw = dt > Scalar(0) ? (error - error_last) / dt : Scalar(0);
      derivative += low_pass_alpha(g.fltd, dt) * (raw - derivative);
    }
    if (g.i > Scalar(0)) {
      const Scalar next = integrator + error * g.i * dt;
      if (!limited || std::abs(next) < std::abs(integrator)) integrator = next;
      integrator = std::max(-g.imax, std::min(g.imax, integrator));
    } else {
      integrator = Scalar(0);
    }
    return g.p * error + integrator + g.d * derivative + g.ff * target;
  }
};

}  // namespace neurov::ardusub
