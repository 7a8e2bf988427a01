// The BlueROV2 Heavy's eight thrusters: four horizontal, vectored at 45 deg
// in an X, and four vertical. The layout's topology (which thruster sits
// where, and the 45 deg) is the vehicle's; the POSITIONS BELOW ARE AN
// ASSUMPTION, not taken from Blue Robotics' drawings: they place the
// thrusters inside the Heavy's published envelope (457 x 571 x 254 mm) and
// must be replaced by the drawings' numbers, with their citation, before
// the vehicle's results are quoted as the BlueROV2 Heavy's.
//
// Body axes: x forward, y starboard, z down. The thrust directions for a
// positive command are also an assumption (motor direction settings on the
// real vehicle decide them): with all four horizontal thrusters positive
// the vehicle surges; the thrust lines form an X.
#pragma once

#include <array>
#include <cmath>

#include "neurov/model/thruster_geometry.hpp"

namespace neurov {

/// Names in the order of bluerov2_heavy_assumed_layout(); port and starboard
/// follow the sign of y (starboard is +y).
inline constexpr std::array<const char*, 8> kBlueRov2HeavyThrusterNames = {
    "bow_starboard_horizontal",  "bow_port_horizontal",     "stern_starboard_horizontal",
    "stern_port_horizontal",     "bow_starboard_vertical",  "bow_port_vertical",
    "stern_starboard_vertical",  "stern_port_vertical"};

/// Assumed positions [m]: horizontal thrusters at (+-0.156, +-0.111, 0.085),
/// vertical thrusters at (+-0.120, +-0.218, 0.000) (assumed, see above).
template <typename Scalar>
inline std::array<ThrusterGeometry<Scalar>, 8> bluerov2_heavy_assumed_layout() noexcept {
  const Scalar h = static_cast<Scalar>(std::sqrt(0.5));
  const Scalar hx = Scalar(0.156), hy = Scalar(0.111), hz = Scalar(0.085);
  const Scalar vx = Scalar(0.120), vy = Scalar(0.218), vz = Scalar(0);
  std::array<ThrusterGeometry<Scalar>, 8> g;
  // Horizontal: heading of the thrust -45, +45, +45, -45 deg (an X).
  g[0] = {Vector3<Scalar>(hx, hy, hz), Vector3<Scalar>(h, -h, Scalar(0))};
  g[1] = {Vector3<Scalar>(hx, -hy, hz), Vector3<Scalar>(h, h, Scalar(0))};
  g[2] = {Vector3<Scalar>(-hx, hy, hz), Vector3<Scalar>(h, h, Scalar(0))};
  g[3] = {Vector3<Scalar>(-hx, -hy, hz), Vector3<Scalar>(h, -h, Scalar(0))};
  // Vertical: positive thrust pushes down (+z).
  g[4] = {Vector3<Scalar>(vx, vy, vz), Vector3<Scalar>(Scalar(0), Scalar(0), Scalar(1))};
  g[5] = {Vector3<Scalar>(vx, -vy, vz), Vector3<Scalar>(Scalar(0), Scalar(0), Scalar(1))};
  g[6] = {Vector3<Scalar>(-vx, vy, vz), Vector3<Scalar>(Scalar(0), Scalar(0), Scalar(1))};
  g[7] = {Vector3<Scalar>(-vx, -vy, vz), Vector3<Scalar>(Scalar(0), Scalar(0), Scalar(1))};
  return g;
}

}  // namespace neurov
