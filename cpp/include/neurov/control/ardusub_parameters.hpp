// ArduSub's parameters that its stabilize, depth-hold and position-hold
// control reads, by ArduSub's own names, described once: default, the range
// ArduSub's parameter reference documents (ardupilot.org/sub/docs/
// parameters-Sub-stable-V4.1.2.html), unit and meaning. The defaults are
// ArduSub's (its attitude controller's Sub defaults; the position
// controller's where Sub sets none). ArduSub stores angles in centidegrees
// and distances in centimetres: so do these.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <tuple>
#include <utility>

#include "neurov/core/field_spec.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

namespace neurov {

/// Rows a PWM -> thrust table of the controller can hold.
inline constexpr int kArduSubCurveRows = 16;
/// Motors of the largest frame modelled (vectored 6DOF, BlueROV2 Heavy).
inline constexpr int kArduSubMaxMotors = 8;

/// The flight modes modelled (ArduSub's mode names).
/// One column of the controller's PWM -> thrust table.
template <typename Scalar>
using ArduSubCurve = Eigen::Matrix<Scalar, kArduSubCurveRows, 1>;

enum class ArduSubMode : int { stabilize = 0, depth_hold = 1, position_hold = 2 };

template <typename Scalar>
struct ArduSubConfig;

namespace detail {
template <typename Scalar>
constexpr auto ardusub_parameter_table() noexcept;
}  // namespace detail

template <typename Scalar>
struct ArduSubConfig {
  // Attitude controller (AC_AttitudeControl): angle P, acceleration limits,
  // input shaping.
  Scalar ATC_ANG_RLL_P, ATC_ANG_PIT_P, ATC_ANG_YAW_P;
  Scalar ATC_ACCEL_R_MAX, ATC_ACCEL_P_MAX, ATC_ACCEL_Y_MAX;
  Scalar ATC_INPUT_TC, ATC_RATE_FF_ENAB, ANGLE_MAX;
  // Rate PIDs, roll, pitch, yaw.
  Scalar ATC_RAT_RLL_P, ATC_RAT_RLL_I, ATC_RAT_RLL_D, ATC_RAT_RLL_FF, ATC_RAT_RLL_IMAX,
      ATC_RAT_RLL_FLTT, ATC_RAT_RLL_FLTE, ATC_RAT_RLL_FLTD;
  Scalar ATC_RAT_PIT_P, ATC_RAT_PIT_I, ATC_RAT_PIT_D, ATC_RAT_PIT_FF, ATC_RAT_PIT_IMAX,
      ATC_RAT_PIT_FLTT, ATC_RAT_PIT_FLTE, ATC_RAT_PIT_FLTD;
  Scalar ATC_RAT_YAW_P, ATC_RAT_YAW_I, ATC_RAT_YAW_D, ATC_RAT_YAW_FF, ATC_RAT_YAW_IMAX,
      ATC_RAT_YAW_FLTT, ATC_RAT_YAW_FLTE, ATC_RAT_YAW_FLTD;
  // Vertical position -> velocity -> acceleration (AC_PosControl).
  Scalar PSC_POSZ_P;
  Scalar PSC_VELZ_P, PSC_VELZ_I, PSC_VELZ_D, PSC_VELZ_IMAX, PSC_VELZ_FLTE, PSC_VELZ_FLTD;
  Scalar PSC_ACCZ_P, PSC_ACCZ_I, PSC_ACCZ_D, PSC_ACCZ_FF, PSC_ACCZ_IMAX, PSC_ACCZ_FLTT, PSC_ACCZ_FLTE,
      PSC_ACCZ_FLTD;
  Scalar PILOT_SPEED_UP, PILOT_SPEED_DN, PILOT_ACCEL_Z;
  // Horizontal position -> velocity (AC_PosControl), into forward/lateral.
  Scalar PSC_POSXY_P;
  Scalar PSC_VELXY_P, PSC_VELXY_I, PSC_VELXY_D, PSC_VELXY_IMAX, PSC_VELXY_FLTE, PSC_VELXY_FLTD;
  Scalar WPNAV_SPEED, WPNAV_ACCEL;
  // Motors (AP_Motors6DOF).
  Scalar FRAME_CONFIG, MOT_PWM_MIN, MOT_PWM_MAX;
  Scalar MOT_1_DIRECTION, MOT_2_DIRECTION, MOT_3_DIRECTION, MOT_4_DIRECTION, MOT_5_DIRECTION,
      MOT_6_DIRECTION, MOT_7_DIRECTION, MOT_8_DIRECTION;
  Scalar SCHED_LOOP_RATE;

  // neurov's side: the mode, the period between two calls, and the ESC's
  // PWM -> thrust table the controller's wrench is computed with.
  /// 0 stabilize, 1 depth hold, 2 position hold (ArduSubMode).
  Scalar mode = Scalar(1);
  /// Control period of the loop that calls step() [s]: the controller runs
  /// round(dt SCHED_LOOP_RATE) of its own iterations per call.
  Scalar dt = Scalar(0.0025);
  /// PWM [us] of the thrust table's rows, increasing (rows past curve_rows unused).
  ArduSubCurve<Scalar> curve_pwm = ArduSubCurve<Scalar>::Zero();
  /// Thrust [N] at each PWM of curve_pwm.
  ArduSubCurve<Scalar> curve_thrust = ArduSubCurve<Scalar>::Zero();
  /// Rows of the table used, 2..16.
  Scalar curve_rows = Scalar(3);

  /// Every ArduSub parameter at ArduSub's default; the thrust table the
  /// T200's ends at 16 V (-39.9 N at 1100 us, 0 at 1500, +51.5 N at 1900:
  /// the vehicle file's curve, which a scenario puts in its place).
  ArduSubConfig() noexcept {
    std::apply([this](const auto&... p) { ((this->*(p.member) = Scalar(p.default_value)), ...); },
               detail::ardusub_parameter_table<Scalar>());
    curve_pwm.template head<3>() << Scalar(1100), Scalar(1500), Scalar(1900);
    curve_thrust.template head<3>() << Scalar(-39.913), Scalar(0), Scalar(51.485);
  }

  ArduSubMode flight_mode() const noexcept { return static_cast<ArduSubMode>(static_cast<int>(mode)); }
  Scalar direction(int motor) const noexcept {
    const Scalar d[kArduSubMaxMotors] = {MOT_1_DIRECTION, MOT_2_DIRECTION, MOT_3_DIRECTION,
                                          MOT_4_DIRECTION, MOT_5_DIRECTION, MOT_6_DIRECTION,
                                          MOT_7_DIRECTION, MOT_8_DIRECTION};
    return d[motor];
  }
};

namespace detail {

template <typename Scalar>
constexpr auto ardusub_parameter_table() noexcept {
  using C = ArduSubConfig<Scalar>;
  const auto P = [](const char* name, Scalar C::*member, double def, double min, double max,
                    const char* unit, const char* doc) constexpr noexcept {
    return parameter_spec<C, Scalar>(name, member, def, min, max, unit, doc);
  };
  const char* hz = "Hz";
  const char* none = "";
  return std::make_tuple(
      P("ATC_ANG_RLL_P", &C::ATC_ANG_RLL_P, 6, 0, 12, "1/s", "Roll angle P: roll rate asked per roll angle error."),
      P("ATC_ANG_PIT_P", &C::ATC_ANG_PIT_P, 6, 0, 12, "1/s", "Pitch angle P: pitch rate asked per pitch angle error."),
      P("ATC_ANG_YAW_P", &C::ATC_ANG_YAW_P, 6, 0, 12, "1/s", "Yaw angle P: yaw rate asked per yaw angle error."),
      P("ATC_ACCEL_R_MAX", &C::ATC_ACCEL_R_MAX, 110000, 0, 180000, "cdeg/s/s", "Largest roll acceleration of the shaped target and the angle controller (0: none)."),
      P("ATC_ACCEL_P_MAX", &C::ATC_ACCEL_P_MAX, 110000, 0, 180000, "cdeg/s/s", "Largest pitch acceleration of the shaped target and the angle controller (0: none)."),
      P("ATC_ACCEL_Y_MAX", &C::ATC_ACCEL_Y_MAX, 110000, 0, 180000, "cdeg/s/s", "Largest yaw acceleration of the shaped target and the angle controller (0: none)."),
      P("ATC_INPUT_TC", &C::ATC_INPUT_TC, 0.15, 0, 1, "s", "Attitude input time constant: the shaped target approaches the commanded angle with this time constant."),
      P("ATC_RATE_FF_ENAB", &C::ATC_RATE_FF_ENAB, 1, 0, 1, none, "1: input shaping and the target's rate fed forward; 0: the target jumps to the command."),
      P("ANGLE_MAX", &C::ANGLE_MAX, 3000, 1000, 8000, "cdeg", "Largest roll and pitch target (and lean angle of position hold)."),
      P("ATC_RAT_RLL_P", &C::ATC_RAT_RLL_P, 0.135, 0, 0.3, none, "Roll rate P: roll output per rad/s of rate error."),
      P("ATC_RAT_RLL_I", &C::ATC_RAT_RLL_I, 0.09, 0, 0.5, none, "Roll rate I."),
      P("ATC_RAT_RLL_D", &C::ATC_RAT_RLL_D, 0.0036, 0, 0.05, none, "Roll rate D."),
      P("ATC_RAT_RLL_FF", &C::ATC_RAT_RLL_FF, 0, 0, 0.5, none, "Roll rate feed-forward: output per rad/s of target rate."),
      P("ATC_RAT_RLL_IMAX", &C::ATC_RAT_RLL_IMAX, 0.444, 0, 1, none, "Largest roll I term."),
      P("ATC_RAT_RLL_FLTT", &C::ATC_RAT_RLL_FLTT, 30, 1, 100, hz, "Roll target filter (0: off)."),
      P("ATC_RAT_RLL_FLTE", &C::ATC_RAT_RLL_FLTE, 0, 0, 100, hz, "Roll error filter (0: off)."),
      P("ATC_RAT_RLL_FLTD", &C::ATC_RAT_RLL_FLTD, 30, 0, 100, hz, "Roll derivative filter (0: off)."),
      P("ATC_RAT_PIT_P", &C::ATC_RAT_PIT_P, 0.135, 0, 0.3, none, "Pitch rate P: pitch output per rad/s of rate error."),
      P("ATC_RAT_PIT_I", &C::ATC_RAT_PIT_I, 0.09, 0, 0.5, none, "Pitch rate I."),
      P("ATC_RAT_PIT_D", &C::ATC_RAT_PIT_D, 0.0036, 0, 0.05, none, "Pitch rate D."),
      P("ATC_RAT_PIT_FF", &C::ATC_RAT_PIT_FF, 0, 0, 0.5, none, "Pitch rate feed-forward."),
      P("ATC_RAT_PIT_IMAX", &C::ATC_RAT_PIT_IMAX, 0.444, 0, 1, none, "Largest pitch I term."),
      P("ATC_RAT_PIT_FLTT", &C::ATC_RAT_PIT_FLTT, 30, 1, 100, hz, "Pitch target filter (0: off)."),
      P("ATC_RAT_PIT_FLTE", &C::ATC_RAT_PIT_FLTE, 0, 0, 100, hz, "Pitch error filter (0: off)."),
      P("ATC_RAT_PIT_FLTD", &C::ATC_RAT_PIT_FLTD, 30, 0, 100, hz, "Pitch derivative filter (0: off)."),
      P("ATC_RAT_YAW_P", &C::ATC_RAT_YAW_P, 0.18, 0, 1, none, "Yaw rate P: yaw output per rad/s of rate error."),
      P("ATC_RAT_YAW_I", &C::ATC_RAT_YAW_I, 0.018, 0, 0.5, none, "Yaw rate I."),
      P("ATC_RAT_YAW_D", &C::ATC_RAT_YAW_D, 0, 0, 0.02, none, "Yaw rate D."),
      P("ATC_RAT_YAW_FF", &C::ATC_RAT_YAW_FF, 0, 0, 0.5, none, "Yaw rate feed-forward."),
      P("ATC_RAT_YAW_IMAX", &C::ATC_RAT_YAW_IMAX, 0.222, 0, 1, none, "Largest yaw I term."),
      P("ATC_RAT_YAW_FLTT", &C::ATC_RAT_YAW_FLTT, 5, 1, 50, hz, "Yaw target filter (0: off)."),
      P("ATC_RAT_YAW_FLTE", &C::ATC_RAT_YAW_FLTE, 0, 0, 20, hz, "Yaw error filter (0: off)."),
      P("ATC_RAT_YAW_FLTD", &C::ATC_RAT_YAW_FLTD, 5, 0, 50, hz, "Yaw derivative filter (0: off)."),
      P("PSC_POSZ_P", &C::PSC_POSZ_P, 3, 1, 3, "1/s", "Vertical position P: climb rate asked per depth error."),
      P("PSC_VELZ_P", &C::PSC_VELZ_P, 8, 1, 8, "1/s", "Vertical velocity P: acceleration asked per climb rate error."),
      P("PSC_VELZ_I", &C::PSC_VELZ_I, 0, 0, 10, "1/s/s", "Vertical velocity I."),
      P("PSC_VELZ_D", &C::PSC_VELZ_D, 0, 0, 1, none, "Vertical velocity D."),
      P("PSC_VELZ_IMAX", &C::PSC_VELZ_IMAX, 1000, 1, 1000, "cm/s/s", "Largest vertical velocity I term."),
      P("PSC_VELZ_FLTE", &C::PSC_VELZ_FLTE, 5, 0, 100, hz, "Vertical velocity error filter (0: off)."),
      P("PSC_VELZ_FLTD", &C::PSC_VELZ_FLTD, 5, 0, 100, hz, "Vertical velocity derivative filter (0: off)."),
      P("PSC_ACCZ_P", &C::PSC_ACCZ_P, 0.5, 0.2, 1.5, none, "Vertical acceleration P: throttle (x1000) per cm/s/s of acceleration error."),
      P("PSC_ACCZ_I", &C::PSC_ACCZ_I, 0.1, 0, 3, none, "Vertical acceleration I."),
      P("PSC_ACCZ_D", &C::PSC_ACCZ_D, 0, 0, 0.4, none, "Vertical acceleration D."),
      P("PSC_ACCZ_FF", &C::PSC_ACCZ_FF, 0, 0, 0.5, none, "Vertical acceleration feed-forward: throttle (x1000) per cm/s/s of acceleration target."),
      P("PSC_ACCZ_IMAX", &C::PSC_ACCZ_IMAX, 800, 0, 1000, "d%", "Largest vertical acceleration I term (throttle x1000)."),
      P("PSC_ACCZ_FLTT", &C::PSC_ACCZ_FLTT, 0, 0, 100, hz, "Vertical acceleration target filter (0: off)."),
      P("PSC_ACCZ_FLTE", &C::PSC_ACCZ_FLTE, 20, 0, 100, hz, "Vertical acceleration error filter (0: off)."),
      P("PSC_ACCZ_FLTD", &C::PSC_ACCZ_FLTD, 0, 0, 100, hz, "Vertical acceleration derivative filter (0: off)."),
      P("PILOT_SPEED_UP", &C::PILOT_SPEED_UP, 50, 20, 500, "cm/s", "Largest climb rate the depth controller asks."),
      P("PILOT_SPEED_DN", &C::PILOT_SPEED_DN, 50, 20, 500, "cm/s", "Largest descent rate the depth controller asks (0: PILOT_SPEED_UP)."),
      P("PILOT_ACCEL_Z", &C::PILOT_ACCEL_Z, 100, 50, 500, "cm/s/s", "Vertical acceleration limit of the depth controller's square-root stage."),
      P("PSC_POSXY_P", &C::PSC_POSXY_P, 1, 0.5, 2, "1/s", "Horizontal position P: speed asked per position error."),
      P("PSC_VELXY_P", &C::PSC_VELXY_P, 2, 0.1, 6, "1/s", "Horizontal velocity P: acceleration asked per speed error."),
      P("PSC_VELXY_I", &C::PSC_VELXY_I, 1, 0.02, 1, "1/s/s", "Horizontal velocity I."),
      P("PSC_VELXY_D", &C::PSC_VELXY_D, 0.5, 0, 1, none, "Horizontal velocity D."),
      P("PSC_VELXY_IMAX", &C::PSC_VELXY_IMAX, 1000, 0, 4500, "cm/s/s", "Largest horizontal velocity I term."),
      P("PSC_VELXY_FLTE", &C::PSC_VELXY_FLTE, 5, 0, 100, hz, "Horizontal velocity error filter (0: off)."),
      P("PSC_VELXY_FLTD", &C::PSC_VELXY_FLTD, 5, 0, 100, hz, "Horizontal velocity derivative filter (0: off)."),
      P("WPNAV_SPEED", &C::WPNAV_SPEED, 500, 20, 2000, "cm/s", "Largest horizontal speed the position controller asks."),
      P("WPNAV_ACCEL", &C::WPNAV_ACCEL, 100, 50, 500, "cm/s/s", "Horizontal acceleration limit of the position controller's square-root stage."),
      P("FRAME_CONFIG", &C::FRAME_CONFIG, 1, 0, 7, none, "Frame: 1 vectored (BlueROV2, 6 motors), 2 vectored 6DOF (BlueROV2 Heavy, 8 motors); others not modelled."),
      P("MOT_PWM_MIN", &C::MOT_PWM_MIN, 1100, 0, 2000, "PWM", "Lowest PWM ever sent to a motor."),
      P("MOT_PWM_MAX", &C::MOT_PWM_MAX, 1900, 0, 2000, "PWM", "Highest PWM ever sent to a motor."),
      P("MOT_1_DIRECTION", &C::MOT_1_DIRECTION, 1, -1, 1, none, "Motor 1 normal (1) or reversed (-1)."),
      P("MOT_2_DIRECTION", &C::MOT_2_DIRECTION, 1, -1, 1, none, "Motor 2 normal (1) or reversed (-1)."),
      P("MOT_3_DIRECTION", &C::MOT_3_DIRECTION, 1, -1, 1, none, "Motor 3 normal (1) or reversed (-1)."),
      P("MOT_4_DIRECTION", &C::MOT_4_DIRECTION, 1, -1, 1, none, "Motor 4 normal (1) or reversed (-1)."),
      P("MOT_5_DIRECTION", &C::MOT_5_DIRECTION, 1, -1, 1, none, "Motor 5 normal (1) or reversed (-1)."),
      P("MOT_6_DIRECTION", &C::MOT_6_DIRECTION, 1, -1, 1, none, "Motor 6 normal (1) or reversed (-1)."),
      P("MOT_7_DIRECTION", &C::MOT_7_DIRECTION, 1, -1, 1, none, "Motor 7 normal (1) or reversed (-1)."),
      P("MOT_8_DIRECTION", &C::MOT_8_DIRECTION, 1, -1, 1, none, "Motor 8 normal (1) or reversed (-1)."),
      P("SCHED_LOOP_RATE", &C::SCHED_LOOP_RATE, 400, 50, 400, hz, "Main loop rate: the controllers' own period is 1 / SCHED_LOOP_RATE."));
}

}  // namespace detail

/// The parameter table (a FieldSpec per ArduSub name), for bindings and docs.
template <typename Scalar>
constexpr auto ardusub_parameters() noexcept {
  return detail::ardusub_parameter_table<Scalar>();
}

/// What ArduSub would not fly: a non-number, a negative gain, limit or
/// filter, a frame not modelled, a motor direction other than +-1, an empty
/// PWM range. (Values outside the documented ranges are taken, as ArduSub
/// takes them; the Python readers warn about them.)
template <typename Scalar>
inline ValidationError validate(const ArduSubConfig<Scalar>& c) noexcept {
  ValidationError bad;
  std::apply(
      [&](const auto&... p) {
        const auto check = [&](const auto& spec) {
          if (bad) return;
          const double v = static_cast<double>(c.*(spec.member));
          if (!std::isfinite(v))
            bad = detail::invalid(spec.name, -1, v, "a finite number");
          else if (spec.min >= 0 && v < 0)
            bad = detail::invalid(spec.name, -1, v, ">= 0 (ArduSub flies no negative gain, limit or filter)");
        };
        (check(p), ...);
      },
      ardusub_parameters<Scalar>());
  if (bad) return bad;
  const double frame = static_cast<double>(c.FRAME_CONFIG);
  if (frame != 1 && frame != 2)
    return detail::invalid("FRAME_CONFIG", -1, frame,
                           "1 (vectored, BlueROV2) or 2 (vectored 6DOF, BlueROV2 Heavy): the frames modelled");
  static constexpr const char* kDirections[kArduSubMaxMotors] = {
      "MOT_1_DIRECTION", "MOT_2_DIRECTION", "MOT_3_DIRECTION", "MOT_4_DIRECTION",
      "MOT_5_DIRECTION", "MOT_6_DIRECTION", "MOT_7_DIRECTION", "MOT_8_DIRECTION"};
  for (int i = 0; i < kArduSubMaxMotors; ++i)
    if (std::abs(static_cast<double>(c.direction(i))) != 1.0)
      return detail::invalid(kDirections[i], -1, static_cast<double>(c.direction(i)), "1 or -1");
  if (!(c.MOT_PWM_MAX > c.MOT_PWM_MIN))
    return detail::invalid("MOT_PWM_MAX", -1, static_cast<double>(c.MOT_PWM_MAX), "> MOT_PWM_MIN");
  if (!(c.SCHED_LOOP_RATE > 0))
    return detail::invalid("SCHED_LOOP_RATE", -1, static_cast<double>(c.SCHED_LOOP_RATE), "> 0");
  const double mode = static_cast<double>(c.mode);
  if (mode != 0 && mode != 1 && mode != 2)
    return detail::invalid("mode", -1, mode, "0 (stabilize), 1 (depth_hold) or 2 (position_hold)");
  if (auto e = detail::check_step("dt", static_cast<double>(c.dt))) return e;
  const double rows = static_cast<double>(c.curve_rows);
  if (!(rows >= 2 && rows <= kArduSubCurveRows && rows == std::floor(rows)))
    return detail::invalid("curve_rows", -1, rows, "a whole number of rows, 2 to 16");
  const int n = static_cast<int>(rows);
  if (auto e = detail::check_finite("curve_pwm", c.curve_pwm.head(n))) return e;
  if (auto e = detail::check_finite("curve_thrust", c.curve_thrust.head(n))) return e;
  for (int i = 1; i < n; ++i)
    if (!(c.curve_pwm(i) > c.curve_pwm(i - 1)))
      return detail::invalid("curve_pwm", i, static_cast<double>(c.curve_pwm(i)), "increasing PWM");
  return {};
}

/// The configuration's fields for the generic bindings: every parameter of
/// the table by its ArduSub name, then neurov's own.
template <typename Scalar>
auto config_fields(const ArduSubConfig<Scalar>*) noexcept {
  using C = ArduSubConfig<Scalar>;
  return std::tuple_cat(
      ardusub_parameters<Scalar>(),
      std::make_tuple(
          FieldSpec<C, Scalar>{"mode", &C::mode, "0 stabilize, 1 depth_hold, 2 position_hold."},
          FieldSpec<C, ArduSubCurve<Scalar>>{
              "curve_pwm", &C::curve_pwm, "PWM [us] of the ESC's thrust table, increasing (16,)."},
          FieldSpec<C, ArduSubCurve<Scalar>>{
              "curve_thrust", &C::curve_thrust, "Thrust [N] at each PWM of curve_pwm (16,)."},
          FieldSpec<C, Scalar>{"curve_rows", &C::curve_rows, "Rows of the thrust table used, 2..16."},
          FieldSpec<C, Scalar>{"dt", &C::dt,
                               "Period of the calling loop [s]: round(dt SCHED_LOOP_RATE) "
                               "iterations of ArduSub's loop per step."}));
}

}  // namespace neurov
