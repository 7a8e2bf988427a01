// The allocation matrix of a thruster layout: thruster i at position r_i
// (body axes, from the body origin) pushing along the unit vector d_i adds
// the column [d_i; r_i x d_i] to B, so that tau = B u for thrusts u.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include <Eigen/Core>

#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

namespace neurov {

template <typename Scalar>
struct ThrusterGeometry {
  Vector3<Scalar> position = Vector3<Scalar>::Zero();   ///< r [m], body axes (x fwd, y stbd, z down)
  Vector3<Scalar> direction = Vector3<Scalar>::Zero();  ///< unit thrust direction for positive thrust
};

/// B from the n thrusters at `layout` into `out` (6 x n; a fixed-size
/// matrix or a dynamic one already of that size): untouched unless every
/// position is finite and every direction a unit vector (to 1e-6), each error
/// naming the thruster.
template <typename Scalar, typename Out>
inline ValidationError allocation_matrix(const ThrusterGeometry<Scalar>* layout, std::size_t n,
                                         Eigen::MatrixBase<Out>& out) noexcept {
  for (std::size_t i = 0; i < n; ++i) {
    const int idx = static_cast<int>(i);
    if (!detail::all_finite(layout[i].position))
      return detail::invalid("thrusters.position", idx, std::nan(""), "finite (one row per thruster)");
    const double norm = static_cast<double>(layout[i].direction.norm());
    if (!(std::abs(norm - 1.0) <= 1e-6))
      return detail::invalid("thrusters.direction", idx, norm,
                             "a unit vector (value is its norm)");
  }
  for (std::size_t i = 0; i < n; ++i) {
    const auto& g = layout[i];
    out.col(static_cast<Eigen::Index>(i)).template head<3>() = g.direction;
    out.col(static_cast<Eigen::Index>(i)).template tail<3>() = g.position.cross(g.direction);
  }
  return {};
}

/// B from a layout of N thrusters known at compile time.
template <typename Scalar, std::size_t N>
inline ValidationError allocation_matrix(const std::array<ThrusterGeometry<Scalar>, N>& layout,
                                         Eigen::Matrix<Scalar, 6, static_cast<int>(N)>& out) noexcept {
  return allocation_matrix(layout.data(), N, out);
}

}  // namespace neurov
