// ArduSub's motor mixing for the two BlueROV2 frames, and the ESC's PWM.
//
// Each motor has a factor per input axis (roll, pitch, yaw, throttle,
// forward, lateral): +1 when a positive motor output pushes the vehicle
// along that axis, -1 against it, 0 when ArduSub does not use the motor for
// it. The factors below are read off the frame pages (ardusub.com "Frame
// configurations" / Blue Robotics' BlueROV2 and Heavy motor diagrams: motor
// numbering and each thruster's forward direction) in ArduSub's axes:
// throttle positive is up, while neurov's z is down, so a vertical thruster
// whose forward thrust points down has throttle factor -1. A test checks
// every factor's sign against the thruster geometry of
// neurov/model/bluerov2_heavy.hpp.
//
// The outputs of the vertical motors (roll, pitch, throttle) and of the
// horizontal ones (yaw, forward, lateral) are each scaled down together when
// the largest exceeds 1, so a saturated group keeps its direction; then
// MOT_n_DIRECTION reverses a motor and the output -1..1 becomes the PWM
// 1500 + 400 out, held within [MOT_PWM_MIN, MOT_PWM_MAX].
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>

#include "neurov/control/ardusub_parameters.hpp"
#include "neurov/model/bluerov2_heavy.hpp"

namespace neurov::ardusub {

/// The six input axes, in the order of the factor rows.
enum Axis : int { roll = 0, pitch = 1, yaw = 2, throttle = 3, forward = 4, lateral = 5 };

template <typename Scalar>
using MotorVector = Eigen::Matrix<Scalar, kArduSubMaxMotors, 1>;
template <typename Scalar>
using FactorMatrix = Eigen::Matrix<Scalar, 6, kArduSubMaxMotors>;

/// Motors of FRAME_CONFIG 1 (vectored: 4 vectored horizontal, 2 vertical)
/// or 2 (vectored 6DOF: 4 vectored horizontal, 4 vertical).
inline int frame_motors(int frame) noexcept { return frame == 2 ? 8 : 6; }

/// The factors of a frame (columns past its motors zero).
template <typename Scalar>
FactorMatrix<Scalar> frame_factors(int frame) noexcept {
  FactorMatrix<Scalar> f = FactorMatrix<Scalar>::Zero();
  // Horizontal motors, both frames: 1 bow starboard, 2 bow port, 3 stern
  // starboard, 4 stern port; positive output pushes aft-outward at the bow
  // and forward-inward at the stern.
  f.row(yaw).template head<4>() << 1, -1, -1, 1;
  f.row(forward).template head<4>() << -1, -1, 1, 1;
  f.row(lateral).template head<4>() << 1, -1, 1, -1;
  if (frame == 2) {
    // Vertical motors 5 bow starboard, 6 bow port, 7 stern starboard,
    // 8 stern port; positive output pushes down.
    f.row(roll).template segment<4>(4) << 1, -1, 1, -1;
    f.row(pitch).template segment<4>(4) << -1, -1, 1, 1;
    f.row(throttle).template segment<4>(4) << -1, -1, -1, -1;
  } else {
    // Vertical motors 5 starboard, 6 port, amidships: roll and throttle.
    f.row(roll).template segment<2>(4) << 1, -1;
    f.row(throttle).template segment<2>(4) << -1, -1;
  }
  return f;
}

/// Body wrench [N, N m] per newton of each motor's forward thrust (columns
/// [d; r x d]): the Heavy's layout (neurov/model/bluerov2_heavy.hpp); for the
/// vectored frame its horizontal motors and two vertical ones amidships at
/// the Heavy's lateral offset (no published position of the BlueROV2's).
template <typename Scalar>
Eigen::Matrix<Scalar, 6, kArduSubMaxMotors> frame_wrench_matrix(int frame) noexcept {
  Eigen::Matrix<Scalar, 6, kArduSubMaxMotors> b = Eigen::Matrix<Scalar, 6, kArduSubMaxMotors>::Zero();
  auto layout = bluerov2_heavy_layout<Scalar>();
  if (frame != 2) {
    layout[4].position << Scalar(0), layout[4].position.y(), Scalar(0);
    layout[5].position << Scalar(0), layout[5].position.y(), Scalar(0);
  }
  for (int i = 0; i < frame_motors(frame); ++i) {
    const Vector3<Scalar> d = layout[static_cast<std::size_t>(i)].direction.normalized();
    b.col(i) << d, layout[static_cast<std::size_t>(i)].position.cross(d);
  }
  return b;
}

/// Which input axes a mix had to scale down (vertical group: roll, pitch,
/// throttle; horizontal group: yaw, forward, lateral).
struct MixLimits {
  bool vertical = false;
  bool horizontal = false;
  bool axis(int a) const noexcept { return (a == yaw || a == forward || a == lateral) ? horizontal : vertical; }
};

/// Motor outputs -1..1 from the six inputs (each -1..1) and the factors.
template <typename Scalar>
MixLimits mix(const FactorMatrix<Scalar>& factors, int motors, const Vector6<Scalar>& in,
              MotorVector<Scalar>& out) noexcept {
  MixLimits lim;
  out.setZero();
  Scalar vertical_max = Scalar(0), horizontal_max = Scalar(0);
  MotorVector<Scalar> v = MotorVector<Scalar>::Zero(), h = MotorVector<Scalar>::Zero();
  for (int i = 0; i < motors; ++i) {
    v(i) = factors(roll, i) * in(roll) + factors(pitch, i) * in(pitch) +
           factors(throttle, i) * in(throttle);
    h(i) = factors(yaw, i) * in(yaw) + factors(forward, i) * in(forward) +
           factors(lateral, i) * in(lateral);
    vertical_max = std::max(vertical_max, std::abs(v(i)));
    horizontal_max = std::max(horizontal_max, std::abs(h(i)));
  }
  if (vertical_max > Scalar(1)) {
    v /= vertical_max;
    lim.vertical = true;
  }
  if (horizontal_max > Scalar(1)) {
    h /= horizontal_max;
    lim.horizontal = true;
  }
  out = v + h;
  return lim;
}

/// The PWM of one motor: its output reversed by MOT_n_DIRECTION, 1500 +
/// 400 out, within [MOT_PWM_MIN, MOT_PWM_MAX].
template <typename Scalar>
Scalar motor_pwm(Scalar out, Scalar direction, Scalar pwm_min, Scalar pwm_max) noexcept {
  const Scalar pwm = Scalar(1500) + Scalar(400) * direction * out;
  return std::max(pwm_min, std::min(pwm_max, pwm));
}

/// Thrust [N] of an ESC at this PWM: the table linearly interpolated,
/// clamped to its ends.
template <typename Scalar>
Scalar table_thrust(const ArduSubConfig<Scalar>& c, Scalar pwm) noexcept {
  const int n = static_cast<int>(c.curve_rows);
  if (pwm <= c.curve_pwm(0)) return c.curve_thrust(0);
  for (int i = 1; i < n; ++i)
    if (pwm <= c.curve_pwm(i)) {
      const Scalar t = (pwm - c.curve_pwm(i - 1)) / (c.curve_pwm(i) - c.curve_pwm(i - 1));
      return c.curve_thrust(i - 1) + t * (c.curve_thrust(i) - c.curve_thrust(i - 1));
    }
  return c.curve_thrust(n - 1);
}

}  // namespace neurov::ardusub
