// The small fixed-size symmetric-matrix routines of the vehicle checks and
// M^-1 (symmetric_matrix.hpp): Cholesky and inverse against Eigen's LLT at
// seeded random SPD matrices, refusals of indefinite, singular and
// non-finite matrices, and the smallest eigenvalue against Eigen's solver.
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "neurov/core/symmetric_matrix.hpp"
#include "test_support.hpp"

namespace {

using neurov_test::eps;
using neurov_test::kPoints;
using neurov_test::Rng;

NEUROV_SCALAR_SUITE(SymmetricMatrixTest);

template <typename S, int n>
Eigen::Matrix<S, n, n> random_spd(Rng& rng) {
  Eigen::Matrix<S, n, n> a;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) a(i, j) = rng.uniform<S>(-1.0, 1.0);
  // A A^T plus a diagonal spread over three decades, like M of a real vehicle.
  Eigen::Matrix<S, n, n> m = a * a.transpose();
  for (int i = 0; i < n; ++i) m(i, i) += rng.uniform<S>(0.1, 100.0);
  return m;
}

template <typename S, int n>
void check_against_llt() {
  Rng rng(41 + n);
  for (int k = 0; k < kPoints; ++k) {
    const Eigen::Matrix<S, n, n> m = random_spd<S, n>(rng);
    Eigen::Matrix<S, n, n> l, inv;
    ASSERT_TRUE(neurov::detail::cholesky(m, l));
    const Eigen::Matrix<S, n, n> l_eigen = Eigen::LLT<Eigen::Matrix<S, n, n>>(m).matrixL();
    const S scale = m.cwiseAbs().maxCoeff();
    EXPECT_LE((l - l_eigen).cwiseAbs().maxCoeff(), S(100) * eps<S>() * std::sqrt(scale));
    EXPECT_TRUE(l.template triangularView<Eigen::StrictlyUpper>().toDenseMatrix().isZero(0));
    ASSERT_TRUE(neurov::detail::spd_inverse(m, inv));
    EXPECT_EQ(inv, inv.transpose());  // exactly symmetric, as Vehicle keeps M^-1
    const Eigen::Matrix<S, n, n> id = Eigen::Matrix<S, n, n>::Identity();
    // Residual relative to the condition number's reach.
    const S cond = scale * inv.cwiseAbs().maxCoeff();
    EXPECT_LE((inv * m - id).cwiseAbs().maxCoeff(), S(50) * eps<S>() * cond) << "at point " << k;
  }
}

TYPED_TEST(SymmetricMatrixTest, MatchesEigensLltAndInvertsRandomSpdMatrices) {
  check_against_llt<TypeParam, 3>();
  check_against_llt<TypeParam, 6>();
}

TYPED_TEST(SymmetricMatrixTest, RefusesIndefiniteSingularAndNonFiniteMatricesLeavingTheInverseAlone) {
  using S = TypeParam;
  using M6 = Eigen::Matrix<S, 6, 6>;
  const M6 sentinel = M6::Constant(S(7));
  M6 bad[4];
  bad[0] = M6::Identity();
  bad[0](4, 4) = S(-1);  // indefinite
  bad[1] = M6::Identity();
  bad[1](2, 2) = S(0);  // singular
  bad[2] = M6::Identity();
  bad[2](5, 5) = std::numeric_limits<S>::quiet_NaN();
  bad[3] = M6::Identity();
  bad[3](3, 1) = bad[3](1, 3) = std::numeric_limits<S>::infinity();
  for (const M6& m : bad) {
    M6 l, inv = sentinel;
    EXPECT_FALSE(neurov::detail::cholesky(m, l));
    EXPECT_FALSE(neurov::detail::spd_inverse(m, inv));
    EXPECT_EQ(inv, sentinel);
  }
}

template <typename S, int n>
void check_min_eigenvalue() {
  Rng rng(77 + n);
  for (int k = 0; k < kPoints; ++k) {
    Eigen::Matrix<S, n, n> a;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j <= i; ++j) a(i, j) = a(j, i) = rng.uniform<S>(-10.0, 10.0);
    // Every few points a diagonal matrix, and one with a repeated eigenvalue:
    // the rotations must leave those alone.
    if (k % 5 == 1) a = a.diagonal().asDiagonal();
    if (k % 5 == 2) a = Eigen::Matrix<S, n, n>::Identity() * S(3);
    const S expected = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<S, n, n>>(a).eigenvalues().minCoeff();
    EXPECT_NEAR(neurov::detail::min_eigenvalue(a), expected, S(200) * eps<S>() * a.norm())
        << "at point " << k;
  }
}

TYPED_TEST(SymmetricMatrixTest, SmallestEigenvalueMatchesEigensSolver) {
  check_min_eigenvalue<TypeParam, 3>();
  check_min_eigenvalue<TypeParam, 6>();
}

TYPED_TEST(SymmetricMatrixTest, SmallestEigenvalueReadsOnlyTheLowerTriangle) {
  using S = TypeParam;
  Eigen::Matrix<S, 6, 6> a = Eigen::Matrix<S, 6, 6>::Identity();
  a(4, 1) = S(2);       // lower: eigenvalues of [[1, 2], [2, 1]] are 3 and -1
  a(1, 4) = S(-1000);  // upper: ignored
  EXPECT_NEAR(neurov::detail::min_eigenvalue(a), S(-1), S(10) * eps<S>());
}

}  // namespace
