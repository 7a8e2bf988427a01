// Fixed-size Eigen types used across neurov, templated on the scalar.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <cmath>

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

namespace detail {

/// True when every entry is finite. Eigen's allFinite() compiles, for a
/// 6-vector, to an out-of-line recursive unroller that took a sixth of a
/// closed-loop run; this is a branch-free loop of compares the compiler
/// vectorises. (NaN fails the <=, so no separate isnan.)
template <typename Derived>
inline bool all_finite(const Eigen::DenseBase<Derived>& m) noexcept {
  using S = typename Derived::Scalar;
  const auto& d = m.derived();
  bool ok = true;
  for (Eigen::Index j = 0; j < d.cols(); ++j)
    for (Eigen::Index i = 0; i < d.rows(); ++i)
      ok &= std::abs(d.coeff(i, j)) <= Eigen::NumTraits<S>::highest();
  return ok;
}

template <typename A, typename B, typename... Rest>
inline bool all_finite(const A& a, const B& b, const Rest&... rest) noexcept {
  // Bitwise & on ints: one branch for the whole set (and no clang
  // -Wbitwise-instead-of-logical in users' builds).
  return ((static_cast<int>(all_finite(a)) & static_cast<int>(all_finite(b))) & ... &
          static_cast<int>(all_finite(rest))) != 0;
}

}  // namespace detail

}  // namespace neurov
