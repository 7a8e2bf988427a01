// The waves of SimulationConfig::waves (Waves, on the run's
// RandomStream::waves): their kinematics followed at the vehicle once per
// control period, with their rates along its path, and interpolated in time
// through the substeps and RK4 stages (WaveInterval, rk4_step_in_flow).
#pragma once

#include "neurov/model/flow.hpp"
#include "neurov/model/kinematics.hpp"
#include "neurov/sim/disturbances/part.hpp"
#include "neurov/sim/flags.hpp"
#include "neurov/sim/sea_constants.hpp"
#include "neurov/sim/waves.hpp"

namespace neurov::parts {

template <typename Scalar>
struct SeaWaves : PartDefaults<Scalar> {
  /// Its scenario table [waves]: SimulationConfig's field of the same name.
  static constexpr const char* kTable = "waves";
  using Vec3 = Vector3<Scalar>;
  using Vec6 = Vector6<Scalar>;
  struct State {
    Waves<Scalar> waves;
    WaveInterval<Scalar> period;  ///< the waves over this control period
  };

  template <typename C>
  static ValidationError validate(const C& c) noexcept {
    if (c.waves) return neurov::validate(*c.waves, Waves<Scalar>::capacity);
    return {};
  }

  template <typename C>
  static void reset(const C& c, State& s, std::uint64_t seed, const Plant<Scalar>& p) noexcept {
    if (!c.waves) return;
    Waves<Scalar>::create(*c.waves, seed, s.waves);
    s.waves.start(0.0, p.eta.template head<3>(), c.dt, ned_velocity(p));
  }

  template <typename C>
  static void current(const C& c, const State& s, Substep<Scalar>& sub) noexcept {
    if (c.waves) sub.waves = &s.waves;
  }

  template <typename C>
  static void log(const C& c, const State& s, Eigen::Index row,
                  SimulationResult<Scalar>& r) noexcept {
    if (!c.waves) return;
    r.wave_velocity.row(row) = s.waves.kinematics().velocity.transpose();
    r.wave_elevation(row) = s.waves.kinematics().elevation;
  }

  /// The waves over the control period that starts now, under the force
  /// tau: from where they were followed to (the position predicted for
  /// now), on to the end of the period at the position predicted from the
  /// vehicle's NED velocity u and acceleration b now (off by dt^3 |jerk| / 6),
  /// with their rates along that path; the substeps interpolate between the
  /// two.
  template <typename C>
  static void follow(const C& c, State& s, const Plant<Scalar>& p, const Vec6& tau,
                     const Substep<Scalar>& row) noexcept {
    if (!c.waves) return;
    const Scalar dt = c.dt;
    const Matrix3<Scalar> r = rotation(EulerTrig<Scalar>::from_pose(p.eta));
    const Vec3 u = r * p.nu.template head<3>();
    FluidFlow<Scalar> flow;
    flow.velocity = row.current + s.waves.kinematics().velocity;
    flow.acceleration = s.waves.rates().velocity;
    flow.displaced_mass =
        p.vehicle.parameters().buoyancy / static_cast<Scalar>(standard_gravity);
    Vec6 eta_dot, nu_dot;
    const Status st = derivative_in_flow(p.vehicle, p.eta, p.nu, tau, flow, eta_dot, nu_dot);
    // d(R v)/dt = R (v_dot + w x v); none if the plant cannot say.
    const Vec3 b = (st == Status::ok || st == Status::near_singularity)
                       ? Vec3(r * (nu_dot.template head<3>() +
                                   p.nu.template tail<3>().cross(p.nu.template head<3>())))
                       : Vec3::Zero();
    s.period.duration = dt;
    s.period.start_velocity = s.waves.kinematics().velocity;
    s.period.start_rate = s.waves.rates().velocity;
    s.waves.advance(p.eta.template head<3>() + dt * u + (dt * dt / Scalar(2)) * b, u + dt * b);
    s.period.end_velocity = s.waves.kinematics().velocity;
    s.period.end_rate = s.waves.rates().velocity;
  }

  /// The flow along the vehicle's path at the RK4 stages' times, with its
  /// rate along the path (see WaveInterval), on the substep's current.
  template <typename C>
  static void flow(const C& c, const State& s, const Plant<Scalar>& p,
                   Substep<Scalar>& sub) noexcept {
    if (!c.waves) return;
    if (p.eta(2) < s.waves.minimum_depth()) sub.faults |= fault_bits::shallow;
    sub.in_flow = true;
    s.period.at(sub.offset, sub.start.velocity, sub.start.acceleration);
    s.period.at(sub.offset + sub.h / Scalar(2), sub.mid.velocity, sub.mid.acceleration);
    s.period.at(sub.offset + sub.h, sub.end.velocity, sub.end.acceleration);
    sub.start.velocity += sub.current;
    sub.mid.velocity += sub.current;
    sub.end.velocity += sub.current;
    sub.start.displaced_mass =
        p.vehicle.parameters().buoyancy / static_cast<Scalar>(standard_gravity);
  }

 private:
  static Vec3 ned_velocity(const Plant<Scalar>& p) noexcept {
    return rotation(EulerTrig<Scalar>::from_pose(p.eta)) * p.nu.template head<3>();
  }
};

}  // namespace neurov::parts
