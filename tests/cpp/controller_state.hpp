// What the reliability tests and the fuzzer compare a real-time object by:
// the raw bytes of every piece of state it exposes, so "unchanged" means
// bit-for-bit (NaN == NaN, -0 != +0), and whether that state is finite.
// Also NEROV's thruster layout, which both drive. Free of GoogleTest, so the
// fuzz harness can include it.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "neurov/neurov.hpp"

namespace neurov_test {

class Bytes {
 public:
  template <typename Derived>
  Bytes& add(const Eigen::MatrixBase<Derived>& m) {
    const auto e = m.eval();
    const auto* p = reinterpret_cast<const unsigned char*>(e.data());
    b_.insert(b_.end(), p,
              p + sizeof(typename Derived::Scalar) * static_cast<std::size_t>(e.size()));
    return *this;
  }
  template <typename T>
  Bytes& value(const T& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    b_.insert(b_.end(), p, p + sizeof v);
    return *this;
  }
  bool operator==(const Bytes& o) const { return b_ == o.b_; }

 private:
  std::vector<unsigned char> b_;
};

template <typename S>
Bytes& add_tracking(Bytes& b, const neurov::TrackingError<S>& e) {
  return b.add(e.eta_tilde).add(e.eta_tilde_dot).add(e.s).add(e.eta_r_dot).add(e.eta_r_ddot)
      .add(e.nu_r).add(e.nu_r_dot).add(e.kinematics.R).add(e.kinematics.T);
}

template <typename S, int N>
Bytes state_of(const neurov::NNAdaptiveController<S, N>& c) {
  Bytes b;
  b.add(c.weights()).value(c.weight_norm()).add(c.network_output()).add(c.learning_rates())
      .add(c.basis()).value(c.adapted());
  return add_tracking(b, c.tracking());
}
template <typename S>
Bytes state_of(const neurov::LinearAdaptiveController<S>& c) {
  Bytes b;
  b.add(c.theta()).add(c.model_output());
  return add_tracking(b, c.tracking());
}
template <typename S>
Bytes state_of(const neurov::PDController<S>& c) {
  Bytes b;
  return add_tracking(b, c.tracking());
}
template <typename S>
Bytes state_of(const neurov::PIDController<S>& c) {
  Bytes b;
  b.add(c.integral());
  return add_tracking(b, c.tracking());
}
/// ArduSub: every integrator and filter, the shaped target, the motors.
template <typename S>
Bytes state_of(const neurov::ArduSubController<S>& c) {
  Bytes b;
  const auto& s = c.internals();
  b.add(s.attitude_target).add(s.target_rate).add(s.rate_target).add(s.inputs).add(s.outputs)
      .add(s.pwm).value(s.climb_rate).value(s.started);
  for (const auto* p : {&s.rate[0], &s.rate[1], &s.rate[2], &s.vel_z, &s.accel_z, &s.vel_xy[0], &s.vel_xy[1]})
    b.value(p->target).value(p->error).value(p->derivative).value(p->integrator).value(p->started);
  return add_tracking(b, c.tracking());
}
template <typename S>
bool state_finite(const neurov::ArduSubController<S>& c) {
  return c.internals().attitude_target.allFinite() && c.internals().pwm.allFinite() &&
         c.tracking().s.allFinite();
}
/// Sliding mode and computed torque: the model's output of the last step.
template <typename Ctl>
auto state_of(const Ctl& c) -> decltype(c.model_output(), Bytes()) {
  Bytes b;
  b.add(c.model_output());
  return add_tracking(b, c.tracking());
}
template <typename S>
Bytes state_of(const neurov::ReferenceModel<S>& r) {
  Bytes b;
  return b.add(r.eta_d()).add(r.nu_d()).add(r.desired().eta_d).add(r.desired().eta_d_dot)
      .add(r.desired().eta_d_ddot);
}

template <typename S, int N>
bool state_finite(const neurov::NNAdaptiveController<S, N>& c) {
  return c.weights().allFinite() && std::isfinite(c.weight_norm()) && c.tracking().s.allFinite();
}
template <typename S>
bool state_finite(const neurov::LinearAdaptiveController<S>& c) {
  return c.theta().allFinite() && c.tracking().s.allFinite();
}
template <typename S>
bool state_finite(const neurov::PDController<S>& c) {
  return c.tracking().s.allFinite();
}
template <typename S>
bool state_finite(const neurov::PIDController<S>& c) {
  return c.integral().allFinite() && c.tracking().s.allFinite();
}
template <typename Ctl>
auto state_finite(const Ctl& c) -> decltype(c.model_output(), bool()) {
  return c.model_output().allFinite() && c.tracking().s.allFinite();
}

/// The thruster layout of vehicles/nerov.toml: columns [d; r x d], every
/// thruster limited to +-max_thrust [N].
template <typename S>
neurov::ThrusterConfig<S> nerov_thrusters(S max_thrust = S(250)) {
  const double pos[6][3] = {{-0.5, 0.3, 0}, {-0.5, -0.3, 0}, {0.4, 0, 0},
                            {0.4, 0, 0},    {-0.4, 0.3, 0},  {-0.4, -0.3, 0}};
  const double dir[6][3] = {{1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  neurov::ThrusterConfig<S> c;
  c.matrix.resize(6, 6);
  for (int j = 0; j < 6; ++j) {
    const Eigen::Vector3d r(pos[j][0], pos[j][1], pos[j][2]), d(dir[j][0], dir[j][1], dir[j][2]);
    c.matrix.col(j) << d.cast<S>(), r.cross(d).cast<S>();
  }
  c.max_thrust = neurov::ThrusterConfig<S>::Vector::Constant(6, max_thrust);
  c.min_thrust = -c.max_thrust;
  return c;
}

}  // namespace neurov_test
