// Fixed-size Eigen types used across neurov, templated on the scalar.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace neurov {

template <typename Scalar>
using Vector3 = Eigen::Matrix<Scalar, 3, 1>;
template <typename Scalar>
using Vector6 = Eigen::Matrix<Scalar, 6, 1>;
template <typename Scalar>
using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;
template <typename Scalar>
using Matrix6 = Eigen::Matrix<Scalar, 6, 6>;

/// Skew-symmetric cross-product matrix: skew(a) * b == a.cross(b).
template <typename Scalar>
inline Matrix3<Scalar> skew(const Vector3<Scalar>& a) noexcept {
  Matrix3<Scalar> s;
  s << Scalar(0), -a.z(), a.y(),  //
      a.z(), Scalar(0), -a.x(),   //
      -a.y(), a.x(), Scalar(0);
  return s;
}

}  // namespace neurov
