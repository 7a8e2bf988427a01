// ArduSub's stabilize, depth-hold and position-hold control as its
// documentation describes it (docs/ardusub.md: each stage with its page):
//
//   attitude   the commanded roll, pitch and yaw (the desired path's,
//              roll and pitch within ANGLE_MAX) shaped into a moving target
//              (square-root controller with P = 1 / ATC_INPUT_TC and the
//              ATC_ACCEL_x_MAX limits, the target's rate changing by at most
//              that acceleration); the error to the target into a body rate
//              by the square-root controller with ATC_ANG_x_P and half the
//              acceleration limit, plus the target's rate fed forward; the
//              rate PIDs (ATC_RAT_x_*) into roll, pitch, yaw outputs -1..1.
//   vertical   (depth hold, position hold) depth error [cm] -> climb rate by
//              the square-root controller (PSC_POSZ_P, PILOT_ACCEL_Z) plus
//              the path's climb rate, within PILOT_SPEED_UP/DN -> vertical
//              acceleration by the PID PSC_VELZ_* plus the path's -> throttle
//              by the PID PSC_ACCZ_* on the measured acceleration, x 0.001 as
//              throttle 0..1 about its neutral 0.5, i.e. x 0.002 as thrust
//              -1..1.
//   horizontal (position hold) position error [cm] -> velocity by the
//              square-root controller (PSC_POSXY_P, WPNAV_ACCEL) plus the
//              path's, within WPNAV_SPEED -> acceleration by the PIDs
//              PSC_VELXY_* plus the path's -> lean angles as a multicopter
//              would fly them (pitch = atan(-a_forward / g), roll =
//              atan(a_right cos(pitch) / g), within ANGLE_MAX) -> forward =
//              -sin(pitch), lateral = sin(roll): Sub translates the lean
//              angles into thrust and stays level.
//   motors     ardusub_motors.hpp: the frame's factors, groups scaled to fit,
//              MOT_n_DIRECTION, PWM within MOT_PWM_MIN/MAX.
//
// Loop rate: ArduSub runs these at SCHED_LOOP_RATE (400 Hz). A step of the
// closed loop (period dt) runs n = round(dt SCHED_LOOP_RATE) (at least 1)
// iterations of period dt / n on the measurement of that step (the
// measurement is held, as a slower sensor would be), and returns the mean of
// their wrenches. With dt = 1 / SCHED_LOOP_RATE the controller is ArduSub's
// loop exactly; at longer periods the held measurement is the approximation.
//
// Output: neurov's controllers give a body wrench. This one gives the wrench
// its PWMs make: each ESC's thrust from the PWM -> thrust table (curve_*,
// the vehicle's thruster curve), along the thruster's forward direction in
// the frame's layout. A motor with MOT_n_DIRECTION = -1 is taken to be
// mounted reversed (that is why a vehicle has it set), so its PWM is
// reversed and its thrust on the vehicle is not. The PWMs are pwm().
//
// The vertical acceleration ArduSub measures with its IMU is here the change
// of the earth-frame vertical velocity between two steps.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "neurov/control/ardusub_motors.hpp"
#include "neurov/control/ardusub_parameters.hpp"
#include "neurov/control/ardusub_stages.hpp"
#include "neurov/control/controller_base.hpp"

namespace neurov {

/// Everything ArduSub's controllers remember between iterations.
template <typename Scalar>
struct ArduSubState {
  Vector3<Scalar> attitude_target = Vector3<Scalar>::Zero();  ///< shaped roll, pitch, yaw [rad]
  Vector3<Scalar> target_rate = Vector3<Scalar>::Zero();      ///< its Euler rates [rad/s]
  Vector3<Scalar> rate_target = Vector3<Scalar>::Zero();      ///< body rates asked [rad/s]
  ardusub::RatePid<Scalar> rate[3];
  ardusub::RatePid<Scalar> vel_z, accel_z, vel_xy[2];
  Vector6<Scalar> inputs = Vector6<Scalar>::Zero();  ///< roll, pitch, yaw, throttle, forward, lateral
  ardusub::MotorVector<Scalar> outputs = ardusub::MotorVector<Scalar>::Zero();
  ardusub::MotorVector<Scalar> pwm = ardusub::MotorVector<Scalar>::Constant(Scalar(1500));
  ardusub::MixLimits limits{};
  Scalar climb_rate = Scalar(0);  ///< last measured climb rate [cm/s]
  bool started = false;
};

template <typename ScalarT>
class ArduSubController
    : public ControllerBase<ArduSubController<ScalarT>, ScalarT, ArduSubConfig<ScalarT>> {
  using Base = ControllerBase<ArduSubController<ScalarT>, ScalarT, ArduSubConfig<ScalarT>>;
  friend Base;

 public:
  using typename Base::Scalar;
  using typename Base::Vec6;
  using Motors = ardusub::MotorVector<Scalar>;
  using Base::step;

  NEUROV_CONTROLLER_NAMES("ardusub", "ArduSub", "ArduSubController")
  NEUROV_CONTROLLER_CONSTRUCTORS(ArduSubController, "ArduSub controller")
  static constexpr const char* kDoc =
      "ArduSub's stabilize / depth-hold / position-hold control by its parameters' names: "
      "attitude (input shaping, square-root angle P, rate PIDs), vertical position-velocity-"
      "acceleration cascade, horizontal position-velocity loops into forward and lateral "
      "thrust, the frame's motor mixing and PWM; tau is the wrench of those PWMs through the "
      "ESC's thrust table. Runs round(dt * SCHED_LOOP_RATE) iterations per step.";

  void reset() noexcept {
    state_ = ArduSubState<Scalar>{};
    const int frame = static_cast<int>(this->config_.FRAME_CONFIG);
    motors_ = ardusub::frame_motors(frame);
    factors_ = ardusub::frame_factors<Scalar>(frame);
    wrench_ = ardusub::frame_wrench_matrix<Scalar>(frame);
    this->reset_common();
  }

  /// tau from the measurement and the desired path; on refusal tau = 0 and
  /// nothing changes.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    TrackingError<Scalar> e;
    if (const Status ts = this->track(eta, nu, eta_d, eta_d_dot, eta_d_ddot, this->lambda(), e, tau);
        ts != Status::ok)
      return ts;
    const auto& c = this->config_;
    const Scalar loops = std::max(Scalar(1), std::round(c.dt * c.SCHED_LOOP_RATE));
    const int n = static_cast<int>(std::min(loops, Scalar(100000)));
    const Scalar h = c.dt / Scalar(n);
    ArduSubState<Scalar> s = state_;
    const Vector3<Scalar> v_earth = e.kinematics.R * nu.template head<3>();
    const Scalar climb = -Scalar(100) * v_earth.z();
    const Scalar accel_up = s.started ? (climb - s.climb_rate) / c.dt : Scalar(0);
    if (!s.started) s.attitude_target = eta.template tail<3>();  // the target starts where the vehicle is
    Vec6 sum = Vec6::Zero();
    for (int k = 0; k < n; ++k) sum += iterate(s, e, eta, nu, eta_d, eta_d_dot, eta_d_ddot, v_earth, accel_up, h);
    s.climb_rate = climb;
    s.started = true;
    const Vec6 tau_new = sum / Scalar(n);
    // Every number remembered must be finite too: a NaN can reach a PWM
    // clamp, which would pass a finite thrust on and keep the NaN inside.
    if (!(tau_new.allFinite() && pack(s).allFinite())) return this->refuse(Status::non_finite_output, tau);
    state_ = s;
    return this->accept(e, tau_new, tau);
  }

  /// Motors of the frame (6 or 8).
  int motors() const noexcept { return motors_; }
  /// PWM [us] of each motor at the last iteration (motors past motors() 1500).
  const Motors& pwm() const noexcept { return state_.pwm; }
  /// Motor outputs -1..1 before MOT_n_DIRECTION, last iteration.
  const Motors& motor_outputs() const noexcept { return state_.outputs; }
  /// The mixer's inputs of the last iteration: roll, pitch, yaw, throttle,
  /// forward, lateral, each -1..1.
  const Vec6& axis_inputs() const noexcept { return state_.inputs; }
  /// The whole state, by part.
  const ArduSubState<Scalar>& internals() const noexcept { return state_; }
  /// The motor stage alone, as ArduSub's manual mode drives it: the PWMs
  /// the frame's mixing, MOT_n_DIRECTION and the PWM range give the six
  /// inputs (roll, pitch, yaw, throttle, forward, lateral, each held within
  /// -1..1). Changes nothing (a replay of a log's inputs against its PWMs).
  Motors mix_pwm(const Vec6& inputs) const noexcept {
    Vec6 in;
    for (int i = 0; i < 6; ++i) in(i) = clamp(inputs(i), Scalar(1));
    Motors outputs;
    ardusub::mix(factors_, motors_, in, outputs);
    return motor_pwms(outputs);
  }

  /// Numbers in the flat state of snapshots: attitude target, its rate, the
  /// rate target (3 each), 7 PIDs x (target, error, derivative, integrator,
  /// started), inputs (6), outputs, PWMs (8 each), the two saturation flags,
  /// the climb rate and started.
  static constexpr int kStateSize = 9 + 7 * 5 + 6 + 16 + 4;
  using StateVector = Eigen::Matrix<Scalar, kStateSize, 1>;
  static constexpr const char* kStateName = "memory";
  static constexpr const char* kStateDoc =
      "Everything the controller remembers between steps, flat (ArduSubController.kStateSize).";

  /// The state as one vector (snapshots, the sampled-loop bridge).
  StateVector state() const noexcept { return pack(state_); }

  /// A snapshot put back (ControllerBase::restore with the flat state);
  /// false, and nothing changed, for a non-finite one.
  bool restore(const TrackingError<Scalar>& e, Status st, const StateVector& v) noexcept {
    if (!this->restorable(e, st) || !v.allFinite()) return false;
    ArduSubState<Scalar> s;
    int k = 0;
    const auto get = [&]() { return v(k++); };
    for (int i = 0; i < 3; ++i) s.attitude_target(i) = get();
    for (int i = 0; i < 3; ++i) s.target_rate(i) = get();
    for (int i = 0; i < 3; ++i) s.rate_target(i) = get();
    for (auto* p : pids(s)) {
      p->target = get(); p->error = get(); p->derivative = get(); p->integrator = get();
      p->started = get() >= Scalar(0.5);
    }
    for (int i = 0; i < 6; ++i) s.inputs(i) = get();
    for (int i = 0; i < kArduSubMaxMotors; ++i) s.outputs(i) = get();
    for (int i = 0; i < kArduSubMaxMotors; ++i) s.pwm(i) = get();
    s.limits.vertical = get() >= Scalar(0.5);
    s.limits.horizontal = get() >= Scalar(0.5);
    s.climb_rate = get();
    s.started = get() >= Scalar(0.5);
    state_ = s;
    return Base::restore(e, st);
  }
  /// The frame's wrench per newton of each motor (6 x 8).
  const Eigen::Matrix<Scalar, 6, kArduSubMaxMotors>& wrench_matrix() const noexcept { return wrench_; }
  /// How far the integrators have moved, for logs.
  Scalar adaptive_norm() const noexcept {
    Scalar s2 = state_.vel_z.integrator * state_.vel_z.integrator +
                state_.accel_z.integrator * state_.accel_z.integrator;
    for (const auto& r : state_.rate) s2 += r.integrator * r.integrator;
    for (const auto& r : state_.vel_xy) s2 += r.integrator * r.integrator;
    return std::sqrt(s2);
  }

 private:
  static StateVector pack(const ArduSubState<Scalar>& s) noexcept {
    StateVector v;
    int k = 0;
    const auto put = [&](Scalar x) { v(k++) = x; };
    for (int i = 0; i < 3; ++i) put(s.attitude_target(i));
    for (int i = 0; i < 3; ++i) put(s.target_rate(i));
    for (int i = 0; i < 3; ++i) put(s.rate_target(i));
    for (const auto* p : pids(s)) {
      put(p->target); put(p->error); put(p->derivative); put(p->integrator); put(p->started ? 1 : 0);
    }
    for (int i = 0; i < 6; ++i) put(s.inputs(i));
    for (int i = 0; i < kArduSubMaxMotors; ++i) put(s.outputs(i));
    for (int i = 0; i < kArduSubMaxMotors; ++i) put(s.pwm(i));
    put(s.limits.vertical ? 1 : 0);
    put(s.limits.horizontal ? 1 : 0);
    put(s.climb_rate);
    put(s.started ? 1 : 0);
    return v;
  }

  template <typename State>
  static auto pids(State& s) noexcept {
    using P = std::conditional_t<std::is_const_v<State>, const ardusub::RatePid<Scalar>*, ardusub::RatePid<Scalar>*>;
    return std::array<P, 7>{&s.rate[0], &s.rate[1], &s.rate[2], &s.vel_z, &s.accel_z, &s.vel_xy[0], &s.vel_xy[1]};
  }

  static Scalar wrap_pi(Scalar a) noexcept {
    const Scalar two_pi = Scalar(2) * Scalar(3.14159265358979323846);
    a = std::fmod(a + Scalar(3.14159265358979323846), two_pi);
    if (a < Scalar(0)) a += two_pi;
    return a - Scalar(3.14159265358979323846);
  }
  static Scalar clamp(Scalar v, Scalar lim) noexcept { return std::max(-lim, std::min(lim, v)); }
  static Scalar cdeg(Scalar v) noexcept { return v * Scalar(3.14159265358979323846) / Scalar(18000); }

  ardusub::PidGains<Scalar> rate_gains(int axis) const noexcept {
    const auto& c = this->config_;
    if (axis == 0)
      return {c.ATC_RAT_RLL_P, c.ATC_RAT_RLL_I, c.ATC_RAT_RLL_D, c.ATC_RAT_RLL_FF,
              c.ATC_RAT_RLL_IMAX, c.ATC_RAT_RLL_FLTT, c.ATC_RAT_RLL_FLTE, c.ATC_RAT_RLL_FLTD};
    if (axis == 1)
      return {c.ATC_RAT_PIT_P, c.ATC_RAT_PIT_I, c.ATC_RAT_PIT_D, c.ATC_RAT_PIT_FF,
              c.ATC_RAT_PIT_IMAX, c.ATC_RAT_PIT_FLTT, c.ATC_RAT_PIT_FLTE, c.ATC_RAT_PIT_FLTD};
    return {c.ATC_RAT_YAW_P, c.ATC_RAT_YAW_I, c.ATC_RAT_YAW_D, c.ATC_RAT_YAW_FF,
            c.ATC_RAT_YAW_IMAX, c.ATC_RAT_YAW_FLTT, c.ATC_RAT_YAW_FLTE, c.ATC_RAT_YAW_FLTD};
  }

  /// One iteration of ArduSub's loop (period h): the mixer's inputs, the
  /// motors, and the wrench of their PWMs.
  Vec6 iterate(ArduSubState<Scalar>& s, const TrackingError<Scalar>& e, const Vec6& eta,
               const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot, const Vec6& eta_d_ddot,
               const Vector3<Scalar>& v_earth, Scalar accel_up, Scalar h) noexcept {
    const auto& c = this->config_;
    const ArduSubMode mode = c.flight_mode();
    const Scalar angle_max = cdeg(c.ANGLE_MAX);
    Vec6 in = Vec6::Zero();

    // Horizontal position -> lean angles -> forward / lateral thrust.
    Scalar roll_cmd = clamp(eta_d(3), angle_max), pitch_cmd = clamp(eta_d(4), angle_max);
    if (mode == ArduSubMode::position_hold) {
      Eigen::Matrix<Scalar, 2, 1> err = Scalar(100) * (eta_d.template head<2>() - eta.template head<2>());
      const Scalar dist = err.norm();
      Eigen::Matrix<Scalar, 2, 1> vel = Eigen::Matrix<Scalar, 2, 1>::Zero();
      if (dist > Scalar(0))
        vel = err * (ardusub::sqrt_controller(dist, c.PSC_POSXY_P, c.WPNAV_ACCEL, h) / dist);
      vel += Scalar(100) * eta_d_dot.template head<2>();
      if (vel.norm() > c.WPNAV_SPEED) vel *= c.WPNAV_SPEED / vel.norm();
      const ardusub::PidGains<Scalar> g{c.PSC_VELXY_P, c.PSC_VELXY_I, c.PSC_VELXY_D, Scalar(0),
                                        c.PSC_VELXY_IMAX, Scalar(0), c.PSC_VELXY_FLTE, c.PSC_VELXY_FLTD};
      Scalar a[2];
      for (int i = 0; i < 2; ++i)
        a[i] = s.vel_xy[i].update(g, vel(i), Scalar(100) * v_earth(i), h, s.limits.horizontal) +
               Scalar(100) * eta_d_ddot(i);
      const Scalar cy = std::cos(eta(5)), sy = std::sin(eta(5)), gravity = Scalar(980.665);
      const Scalar a_fwd = cy * a[0] + sy * a[1], a_right = -sy * a[0] + cy * a[1];
      const Scalar lean_pitch = clamp(std::atan(-a_fwd / gravity), angle_max);
      const Scalar lean_roll = clamp(std::atan(a_right * std::cos(lean_pitch) / gravity), angle_max);
      in(ardusub::forward) = -std::sin(lean_pitch);
      in(ardusub::lateral) = std::sin(lean_roll);
    }

    // Attitude: shaped target, angle controller, rate PIDs.
    const Scalar target[3] = {roll_cmd, pitch_cmd, eta_d(5)};
    const Scalar accel[3] = {cdeg(c.ATC_ACCEL_R_MAX), cdeg(c.ATC_ACCEL_P_MAX), cdeg(c.ATC_ACCEL_Y_MAX)};
    const Scalar ang_p[3] = {c.ATC_ANG_RLL_P, c.ATC_ANG_PIT_P, c.ATC_ANG_YAW_P};
    const bool shaping = c.ATC_RATE_FF_ENAB > Scalar(0.5) && c.ATC_INPUT_TC > Scalar(0);
    for (int i = 0; i < 3; ++i) {
      if (shaping) {
        const Scalar err = wrap_pi(target[i] - s.attitude_target(i));
        const Scalar desired = ardusub::sqrt_controller(err, Scalar(1) / c.ATC_INPUT_TC, accel[i], h);
        s.target_rate(i) = ardusub::shape_rate(s.target_rate(i), desired, accel[i], h);
        s.attitude_target(i) = wrap_pi(s.attitude_target(i) + s.target_rate(i) * h);
      } else {
        s.attitude_target(i) = target[i];
        s.target_rate(i) = Scalar(0);
      }
    }
    Vector3<Scalar> correction;
    for (int i = 0; i < 3; ++i)
      correction(i) = ardusub::sqrt_controller(wrap_pi(s.attitude_target(i) - eta(3 + i)), ang_p[i],
                                               accel[i] / Scalar(2), h);
    s.rate_target = correction + e.kinematics.T_inv * s.target_rate;
    for (int i = 0; i < 3; ++i)
      in(i) = clamp(s.rate[i].update(rate_gains(i), s.rate_target(i), nu(3 + i), h, s.limits.axis(i)),
                    Scalar(1));

    // Vertical cascade [cm, up].
    if (mode != ArduSubMode::stabilize) {
      const Scalar dn = c.PILOT_SPEED_DN > Scalar(0) ? c.PILOT_SPEED_DN : c.PILOT_SPEED_UP;
      Scalar climb_target = ardusub::sqrt_controller(Scalar(100) * (eta(2) - eta_d(2)), c.PSC_POSZ_P,
                                                     c.PILOT_ACCEL_Z, h) -
                            Scalar(100) * eta_d_dot(2);
      climb_target = std::max(-dn, std::min(c.PILOT_SPEED_UP, climb_target));
      const Scalar climb = -Scalar(100) * v_earth.z();
      const ardusub::PidGains<Scalar> gv{c.PSC_VELZ_P, c.PSC_VELZ_I, c.PSC_VELZ_D, Scalar(0),
                                         c.PSC_VELZ_IMAX, Scalar(0), c.PSC_VELZ_FLTE, c.PSC_VELZ_FLTD};
      const Scalar accel_target = s.vel_z.update(gv, climb_target, climb, h, s.limits.vertical) -
                                  Scalar(100) * eta_d_ddot(2);
      const ardusub::PidGains<Scalar> ga{c.PSC_ACCZ_P, c.PSC_ACCZ_I, c.PSC_ACCZ_D, c.PSC_ACCZ_FF,
                                         c.PSC_ACCZ_IMAX, c.PSC_ACCZ_FLTT, c.PSC_ACCZ_FLTE, c.PSC_ACCZ_FLTD};
      const Scalar thr = s.accel_z.update(ga, accel_target, accel_up, h, s.limits.vertical);
      in(ardusub::throttle) = clamp(Scalar(0.002) * thr, Scalar(1));
    }

    // Motors, PWM, and the wrench of the PWMs.
    s.inputs = in;
    s.limits = ardusub::mix(factors_, motors_, in, s.outputs);
    s.pwm = motor_pwms(s.outputs);
    ardusub::MotorVector<Scalar> thrust = ardusub::MotorVector<Scalar>::Zero();
    for (int i = 0; i < motors_; ++i) thrust(i) = c.direction(i) * ardusub::table_thrust(c, s.pwm(i));
    return wrench_ * thrust;
  }

  /// Each motor's PWM from its output -1..1: MOT_n_DIRECTION, the PWM range
  /// (motors past the frame's 1500).
  Motors motor_pwms(const Motors& outputs) const noexcept {
    const auto& c = this->config_;
    Motors pwm = Motors::Constant(Scalar(1500));
    for (int i = 0; i < motors_; ++i)
      pwm(i) = ardusub::motor_pwm(outputs(i), c.direction(i), c.MOT_PWM_MIN, c.MOT_PWM_MAX);
    return pwm;
  }

  ArduSubState<Scalar> state_{};
  int motors_ = 6;
  ardusub::FactorMatrix<Scalar> factors_ = ardusub::FactorMatrix<Scalar>::Zero();
  Eigen::Matrix<Scalar, 6, kArduSubMaxMotors> wrench_ = Eigen::Matrix<Scalar, 6, kArduSubMaxMotors>::Zero();
};

}  // namespace neurov
