// Small fixed-size symmetric matrices: Cholesky factorisation and inverse
// (the 3x3 inertia, the 6x6 mass matrix) and the smallest eigenvalue (is the
// added mass positive semidefinite?).
//
// Why not Eigen::LLT and SelfAdjointEigenSolver: for any size they compile
// blocked paths (rank updates, matrix triangular solves) whose workspace
// falls back to malloc. Those never run at 6x6, but they leave malloc/free
// referenced in a firmware image that must not link an allocator at all (CI
// checks the symbols). The plain algorithms below reference nothing.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>

namespace neurov::detail {

/// Lower-triangular L with L L^T = a, from a's lower triangle. False (and L
/// unspecified) unless a is positive definite with finite entries.
template <typename Scalar, int n>
bool cholesky(const Eigen::Matrix<Scalar, n, n>& a, Eigen::Matrix<Scalar, n, n>& l) noexcept {
  static_assert(n > 0, "cholesky is for fixed sizes");
  l.setZero();
  for (int j = 0; j < n; ++j) {
    Scalar d = a(j, j);
    for (int k = 0; k < j; ++k) d -= l(j, k) * l(j, k);
    // `!(d > 0)` also catches NaN.
    if (!(d > Scalar(0)) || !std::isfinite(d)) return false;
    const Scalar ljj = std::sqrt(d);
    l(j, j) = ljj;
    for (int i = j + 1; i < n; ++i) {
      Scalar s = a(i, j);
      for (int k = 0; k < j; ++k) s -= l(i, k) * l(j, k);
      l(i, j) = s / ljj;
    }
  }
  return true;
}

/// a^-1 for a symmetric positive definite a, through its Cholesky factor;
/// false (inv untouched) if a is not positive definite.
template <typename Scalar, int n>
bool spd_inverse(const Eigen::Matrix<Scalar, n, n>& a, Eigen::Matrix<Scalar, n, n>& inv) noexcept {
  Eigen::Matrix<Scalar, n, n> l;
  if (!cholesky(a, l)) return false;
  // L^-1 by forward substitution, column by column, then a^-1 = L^-T L^-1.
  Eigen::Matrix<Scalar, n, n> li = Eigen::Matrix<Scalar, n, n>::Zero();
  for (int c = 0; c < n; ++c) {
    li(c, c) = Scalar(1) / l(c, c);
    for (int i = c + 1; i < n; ++i) {
      Scalar s(0);
      for (int k = c; k < i; ++k) s -= l(i, k) * li(k, c);
      li(i, c) = s / l(i, i);
    }
  }
  Eigen::Matrix<Scalar, n, n> out;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) {
      Scalar s(0);
      for (int k = i; k < n; ++k) s += li(k, i) * li(k, j);
      out(i, j) = s;
      out(j, i) = s;
    }
  inv = out;
  return true;
}

/// The smallest eigenvalue of the symmetric matrix a (its lower triangle is
/// mirrored), by cyclic Jacobi rotations: a few sweeps suffice at these
/// sizes and the result is accurate to rounding relative to a's norm.
template <typename Scalar, int n>
Scalar min_eigenvalue(const Eigen::Matrix<Scalar, n, n>& a) noexcept {
  Eigen::Matrix<Scalar, n, n> m;
  for (int j = 0; j < n; ++j)
    for (int i = j; i < n; ++i) m(i, j) = m(j, i) = a(i, j);
  for (int sweep = 0; sweep < 50; ++sweep) {
    Scalar off(0), diag(0);
    for (int i = 0; i < n; ++i) {
      diag += m(i, i) * m(i, i);
      for (int j = i + 1; j < n; ++j) off += m(i, j) * m(i, j);
    }
    if (!(off > std::numeric_limits<Scalar>::epsilon() * std::numeric_limits<Scalar>::epsilon() * diag))
      break;
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) {
        if (m(p, q) == Scalar(0)) continue;
        // The rotation that zeroes m(p, q) (Golub & Van Loan, Alg. 8.5.1).
        const Scalar tau = (m(q, q) - m(p, p)) / (Scalar(2) * m(p, q));
        const Scalar t = (tau >= Scalar(0) ? Scalar(1) : Scalar(-1)) /
                         (std::abs(tau) + std::sqrt(Scalar(1) + tau * tau));
        const Scalar c = Scalar(1) / std::sqrt(Scalar(1) + t * t), s = t * c;
        for (int k = 0; k < n; ++k) {
          const Scalar mkp = m(k, p), mkq = m(k, q);
          m(k, p) = c * mkp - s * mkq;
          m(k, q) = s * mkp + c * mkq;
        }
        for (int k = 0; k < n; ++k) {
          const Scalar mpk = m(p, k), mqk = m(q, k);
          m(p, k) = c * mpk - s * mqk;
          m(q, k) = s * mpk + c * mqk;
        }
      }
  }
  return m.diagonal().minCoeff();
}

}  // namespace neurov::detail
