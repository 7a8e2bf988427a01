// The BlueROV2 Heavy's eight thrusters: four horizontal, vectored at 45 deg
// in an X, and four vertical, in ArduSub's motor order for the Heavy
// ("vectored 6DOF" frame: 1 bow starboard, 2 bow port, 3 stern starboard,
// 4 stern port horizontal; 5-8 the vertical ones in the same order).
//
// Positions: von Benzon, Galeazzi, Kristensen, Cole, "An Open-Source
// Benchmark Simulator: Control of a BlueROV2 Underwater Robot", J. Mar. Sci.
// Eng. 10(12):1898, 2022, Appendix A: horizontal thrusters at
// J(alpha_i) (0.156, 0.111, 0.085) m, alpha = {0, 5.05, 1.91, pi} rad,
// vertical ones at J(gamma_i) (0.120, 0.218, 0) m, gamma = {0, 4.15, 1.01,
// pi} rad, J a rotation about z. Those angles give the mirror images of the
// first position to about half a millimetre (5.05 rad puts (0.156, 0.111) at
// (0.1564, -0.1104)); the exact mirror images are used here.
//
// Directions of positive thrust (the thruster's forward direction, in which
// a T200 gives its larger thrust): the signs of ArduSub's motor factors for
// that frame (ArduPilot, libraries/AP_Motors/AP_Motors6DOF.cpp,
// SUB_FRAME_VECTORED_6DOF: forward, lateral, yaw, throttle, roll and pitch
// factors per motor), which Blue Robotics state follow each thruster's
// forward direction (discuss.bluerobotics.com, "BlueROV2 Vectored
// Configuration Throttle Factor"). With them the bow thrusters push aft and outward, the
// stern ones forward and inward, and the vertical ones down.
//
// Body axes: x forward, y starboard, z down.
#pragma once

#include <array>
#include <cmath>

#include "neurov/model/thruster_geometry.hpp"

namespace neurov {

/// Names in the order of bluerov2_heavy_layout(); port and starboard follow
/// the sign of y (starboard is +y).
inline constexpr std::array<const char*, 8> kBlueRov2HeavyThrusterNames = {
    "bow_starboard_horizontal",  "bow_port_horizontal",     "stern_starboard_horizontal",
    "stern_port_horizontal",     "bow_starboard_vertical",  "bow_port_vertical",
    "stern_starboard_vertical",  "stern_port_vertical"};

/// Positions [m] and thrust directions of the eight thrusters (sources above).
template <typename Scalar>
inline std::array<ThrusterGeometry<Scalar>, 8> bluerov2_heavy_layout() noexcept {
  const Scalar h = static_cast<Scalar>(std::sqrt(0.5));
  const Scalar hx = Scalar(0.156), hy = Scalar(0.111), hz = Scalar(0.085);
  const Scalar vx = Scalar(0.120), vy = Scalar(0.218), vz = Scalar(0);
  const Vector3<Scalar> down(Scalar(0), Scalar(0), Scalar(1));
  std::array<ThrusterGeometry<Scalar>, 8> g;
  g[0] = {Vector3<Scalar>(hx, hy, hz), Vector3<Scalar>(-h, h, Scalar(0))};
  g[1] = {Vector3<Scalar>(hx, -hy, hz), Vector3<Scalar>(-h, -h, Scalar(0))};
  g[2] = {Vector3<Scalar>(-hx, hy, hz), Vector3<Scalar>(h, h, Scalar(0))};
  g[3] = {Vector3<Scalar>(-hx, -hy, hz), Vector3<Scalar>(h, -h, Scalar(0))};
  g[4] = {Vector3<Scalar>(vx, vy, vz), down};
  g[5] = {Vector3<Scalar>(vx, -vy, vz), down};
  g[6] = {Vector3<Scalar>(-vx, vy, vz), down};
  g[7] = {Vector3<Scalar>(-vx, -vy, vz), down};
  return g;
}

}  // namespace neurov
