// Euler-angle kinematics: R, T, J, J^-1, J_dot and the EulerKinematics fast
// paths, checked against independent constructions (Eigen's AngleAxis, the
// spec's closed forms, a finite difference) rather than against themselves.
#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "neurov/model/kinematics.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::all_near;
using neurov_test::eps;
using neurov_test::kPi;
using neurov_test::kPoints;
using neurov_test::max_abs;
using neurov_test::Rng;

NEUROV_SCALAR_SUITE(KinematicsTest);

template <typename S>
Vector6<S> pose_with_angles(S phi, S theta, S psi) {
  Vector6<S> eta;
  eta << S(1), S(-2), S(3), phi, theta, psi;
  return eta;
}

TYPED_TEST(KinematicsTest, SkewIsTheCrossProduct) {
  using S = TypeParam;
  Rng rng(11);
  for (int i = 0; i < neurov_test::kPoints; ++i) {
    const Vector3<S> a = rng.vec3<S>(-2, 2), b = rng.vec3<S>(-2, 2);
    EXPECT_TRUE(all_near(skew<S>(a) * b, a.cross(b), 16 * eps<S>()));
    EXPECT_TRUE(all_near(skew<S>(a).transpose(), -skew<S>(a), 0.0));
  }
}

TYPED_TEST(KinematicsTest, RotationIsIdentityAtZeroAngles) {
  using S = TypeParam;
  EXPECT_TRUE(all_near(rotation<S>(S(0), S(0), S(0)), Matrix3<S>::Identity(), 0.0));
  Matrix6<S> j;
  ASSERT_EQ(jacobian<S>(Vector6<S>::Zero(), j), Status::ok);
  EXPECT_TRUE(all_near(j, Matrix6<S>::Identity(), 0.0));
}

TYPED_TEST(KinematicsTest, RotationIsOrthonormalWithUnitDeterminant) {
  using S = TypeParam;
  Rng rng(12);
  const double tol = 16 * eps<S>();
  for (int i = 0; i < kPoints; ++i) {
    // The whole pitch range, poles included: R has no 1/cos(theta).
    const S phi = rng.uniform<S>(-kPi, kPi), theta = rng.uniform<S>(-kPi / 2, kPi / 2),
            psi = rng.uniform<S>(-kPi, kPi);
    const Matrix3<S> r = rotation<S>(phi, theta, psi);
    EXPECT_TRUE(all_near(r.transpose() * r, Matrix3<S>::Identity(), tol)) << "at point " << i;
    EXPECT_NEAR(static_cast<double>(r.determinant()), 1.0, tol) << "at point " << i;
  }
  for (const S theta : {S(kPi / 2), S(-kPi / 2)}) {
    const Matrix3<S> r = rotation<S>(S(0.3), theta, S(-0.7));
    EXPECT_TRUE(all_near(r.transpose() * r, Matrix3<S>::Identity(), tol));
  }
}

TYPED_TEST(KinematicsTest, RotationIsZYXAngleAxisComposition) {
  using S = TypeParam;
  Rng rng(13);
  for (int i = 0; i < kPoints; ++i) {
    const S phi = rng.uniform<S>(-kPi, kPi), theta = rng.uniform<S>(-kPi / 2, kPi / 2),
            psi = rng.uniform<S>(-kPi, kPi);
    const Matrix3<S> expected = (Eigen::AngleAxis<S>(psi, Vector3<S>::UnitZ()) *
                                 Eigen::AngleAxis<S>(theta, Vector3<S>::UnitY()) *
                                 Eigen::AngleAxis<S>(phi, Vector3<S>::UnitX()))
                                    .toRotationMatrix();
    EXPECT_TRUE(all_near(rotation<S>(phi, theta, psi), expected, 16 * eps<S>()))
        << "at point " << i;
    // The pose-based path (EulerKinematics, used by J) builds the same R.
    const auto k = EulerKinematics<S>::from_pose(pose_with_angles(phi, theta, psi));
    if (k.status() == Status::ok) {
      EXPECT_TRUE(all_near(k.R, expected, 16 * eps<S>()));
    }
  }
}

TYPED_TEST(KinematicsTest, AttitudeTransformMatchesSpecClosedForm) {
  using S = TypeParam;
  Rng rng(14);
  for (int i = 0; i < kPoints; ++i) {
    const S phi = rng.uniform<S>(-kPi, kPi), theta = rng.uniform<S>(-1.3, 1.3),
            psi = rng.uniform<S>(-kPi, kPi);
    const double sf = std::sin(double(phi)), cf = std::cos(double(phi));
    const double st = std::sin(double(theta)), ct = std::cos(double(theta));
    Eigen::Matrix3d t, t_inv;
    t << 1, sf * st / ct, cf * st / ct,  //
        0, cf, -sf,                      //
        0, sf / ct, cf / ct;
    t_inv << 1, 0, -st,  //
        0, cf, ct * sf,  //
        0, -sf, ct * cf;
    const auto trig = EulerTrig<S>::from_angles(phi, theta, psi);
    ASSERT_EQ(trig.status, Status::ok);
    // 1/cos(theta) <= 4 here; the float inputs are exact, so only the
    // evaluation rounds.
    EXPECT_TRUE(all_near(attitude_transform(trig), t, 64 * eps<S>())) << "at point " << i;
    EXPECT_TRUE(all_near(attitude_transform_inverse(trig), t_inv, 8 * eps<S>()));
  }
}

TYPED_TEST(KinematicsTest, InverseJacobianInvertsJacobian) {
  using S = TypeParam;
  Rng rng(15);
  for (int i = 0; i < kPoints; ++i) {
    const Vector6<S> eta = rng.pose<S>(1.3);
    Matrix6<S> j, j_inv;
    ASSERT_EQ(jacobian(eta, j), Status::ok);
    ASSERT_EQ(jacobian_inverse(eta, j_inv), Status::ok);
    // T carries 1/cos(theta) and 1/cos^2 in its products; scale the tolerance by it.
    const double sec = 1.0 / std::abs(std::cos(double(eta(4))));
    const double tol = 16 * eps<S>() * sec * sec;
    EXPECT_TRUE(all_near(j_inv * j, Matrix6<S>::Identity(), tol)) << "at point " << i;
    EXPECT_TRUE(all_near(j * j_inv, Matrix6<S>::Identity(), tol)) << "at point " << i;
  }
}

/// J, J^-1 and J_dot at (eta, nu) each report `expected` and still give a
/// finite matrix (written over NaN, so what is checked is what they wrote).
template <typename S>
void expect_jacobians_report(Status expected, const Vector6<S>& eta, const Vector6<S>& nu) {
  Matrix6<S> j = Matrix6<S>::Constant(std::numeric_limits<S>::quiet_NaN()), j_inv = j, j_dot = j;
  EXPECT_EQ(jacobian(eta, j), expected);
  EXPECT_TRUE(j.allFinite());
  EXPECT_EQ(jacobian_inverse(eta, j_inv), expected);
  EXPECT_TRUE(j_inv.allFinite());
  EXPECT_EQ(jacobian_dot(eta, nu, j_dot), expected);
  EXPECT_TRUE(j_dot.allFinite());
}

TYPED_TEST(KinematicsTest, ReportsNearSingularityAtAndJustInsideThreshold) {
  using S = TypeParam;
  const S thr = singularity_threshold<S>();
  const S inside = std::acos(S(0.5) * thr);  // |cos(theta)| = threshold / 2
  const S pitches[] = {S(kPi / 2), S(-kPi / 2), inside, -inside, S(kPi) - inside};
  Vector6<S> nu;
  nu << S(0.5), S(-0.2), S(0.1), S(0.3), S(-0.4), S(0.2);
  for (const S theta : pitches) {
    SCOPED_TRACE(::testing::Message() << "theta = " << theta);
    const Vector6<S> eta = pose_with_angles(S(0.3), theta, S(-1.1));
    const auto trig = EulerTrig<S>::from_pose(eta);
    EXPECT_EQ(trig.status, Status::near_singularity);
    EXPECT_TRUE(attitude_transform(trig).allFinite());
    EXPECT_TRUE(attitude_transform_inverse(trig).allFinite());
    EXPECT_TRUE(attitude_transform_dot(trig, S(0.3), S(-0.2)).allFinite());
    // The clamp keeps the sign of cos(theta), so T keeps pointing the right way;
    // cos_theta itself stays the true cosine, for R, T^-1 and g.
    EXPECT_EQ(std::signbit(trig.sec_theta), std::signbit(std::cos(theta)));
    EXPECT_EQ(std::abs(trig.sec_theta), S(1) / thr);
    EXPECT_EQ(trig.cos_theta, std::cos(theta));

    expect_jacobians_report(Status::near_singularity, eta, nu);
    const auto k = EulerKinematics<S>::from_pose(eta);
    EXPECT_EQ(k.status(), Status::near_singularity);
    EXPECT_TRUE(k.apply(nu).allFinite());
    EXPECT_TRUE(k.apply_dot(nu, nu).allFinite());
    // R needs no division: the clamp must not bend it out of SO(3).
    EXPECT_TRUE(all_near(k.R.transpose() * k.R, Matrix3<S>::Identity(), 16 * eps<S>()));
    EXPECT_TRUE(all_near(k.R, rotation<S>(S(0.3), theta, S(-1.1)), 16 * eps<S>()));
  }
}

TYPED_TEST(KinematicsTest, OkJustOutsideThresholdAndAtPitchOnePointFive) {
  using S = TypeParam;
  const S outside = std::acos(S(2) * singularity_threshold<S>());
  for (const S theta : {S(1.5), S(-1.5), outside, -outside}) {
    SCOPED_TRACE(::testing::Message() << "theta = " << theta);
    const Vector6<S> eta = pose_with_angles(S(-0.4), theta, S(2.0));
    Matrix6<S> j, j_inv, j_dot;
    EXPECT_EQ(jacobian(eta, j), Status::ok);
    EXPECT_EQ(jacobian_inverse(eta, j_inv), Status::ok);
    EXPECT_EQ(jacobian_dot(eta, Vector6<S>(Vector6<S>::Constant(S(0.1))), j_dot), Status::ok);
    EXPECT_TRUE(j.allFinite() && j_inv.allFinite() && j_dot.allFinite());
    EXPECT_EQ(EulerTrig<S>::from_pose(eta).status, Status::ok);
  }
  // At 1.5 rad the unclamped T is still exactly the spec's T.
  const Vector6<S> eta = pose_with_angles(S(0.2), S(1.5), S(0.0));
  Matrix6<S> j;
  ASSERT_EQ(jacobian(eta, j), Status::ok);
  EXPECT_NEAR(double(j(5, 5)), std::cos(double(S(0.2))) / std::cos(double(S(1.5))),
              64 * eps<S>() * 15);
}

TYPED_TEST(KinematicsTest, NonFiniteAngleGivesNonFiniteInputAndFiniteOutput) {
  using S = TypeParam;
  const S bad[] = {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                   -std::numeric_limits<S>::infinity()};
  const Vector6<S> nu = Vector6<S>::Constant(S(0.3));
  for (int angle = 3; angle < 6; ++angle) {
    for (const S value : bad) {
      SCOPED_TRACE(::testing::Message() << "eta(" << angle << ") = " << value);
      Vector6<S> eta = pose_with_angles(S(0.1), S(0.2), S(0.3));
      eta(angle) = value;
      expect_jacobians_report(Status::non_finite_input, eta, nu);
      const auto trig = EulerTrig<S>::from_pose(eta);
      EXPECT_EQ(trig.status, Status::non_finite_input);
      EXPECT_TRUE(attitude_transform(trig).allFinite());
      EXPECT_TRUE(rotation<S>(eta(3), eta(4), eta(5)).allFinite());
    }
  }
  // A non-finite velocity spoils only J_dot, which comes back zero.
  Vector6<S> nu_bad = nu;
  nu_bad(4) = std::numeric_limits<S>::quiet_NaN();
  Matrix6<S> j_dot = Matrix6<S>::Constant(S(7));
  EXPECT_EQ(jacobian_dot(pose_with_angles(S(0.1), S(0.2), S(0.3)), nu_bad, j_dot),
            Status::non_finite_input);
  EXPECT_TRUE(j_dot.isZero(S(0)));
}

// J_dot is the time derivative of J along the motion, so a central difference
// of J along eta_dot = J(eta) nu must reproduce it.
TYPED_TEST(KinematicsTest, JacobianDotMatchesCentralDifferenceAlongMotion) {
  using S = TypeParam;
  // h balances truncation (h^2) against rounding (eps / h); the tolerance is
  // what that balance leaves, with margin.
  const bool is_double = std::is_same<S, double>::value;
  const S h = is_double ? S(1e-6) : S(4e-3);
  const double rel_tol = is_double ? 1e-6 : 1e-3;
  Rng rng(16);
  double worst = 0.0;
  for (int i = 0; i < kPoints; ++i) {
    const Vector6<S> eta = rng.pose<S>(1.2);
    const Vector6<S> nu = rng.velocity<S>();
    Matrix6<S> j;
    ASSERT_EQ(jacobian(eta, j), Status::ok);
    const Vector6<S> eta_dot = j * nu;
    Matrix6<S> j_plus, j_minus, j_dot;
    ASSERT_EQ(jacobian(Vector6<S>(eta + h * eta_dot), j_plus), Status::ok);
    ASSERT_EQ(jacobian(Vector6<S>(eta - h * eta_dot), j_minus), Status::ok);
    const Matrix6<S> fd = (j_plus - j_minus) / (S(2) * h);
    ASSERT_EQ(jacobian_dot(eta, nu, j_dot), Status::ok);
    const double err = max_abs(j_dot - fd) / std::max(1.0, max_abs(j_dot));
    worst = std::max(worst, err);
    EXPECT_LE(err, rel_tol) << "at point " << i << "\nJ_dot =\n" << j_dot << "\nFD =\n" << fd;
  }
  neurov_test::record("worst_relative_error", worst);
}

TYPED_TEST(KinematicsTest, EulerKinematicsProductsEqualFullMatrixProducts) {
  using S = TypeParam;
  Rng rng(17);
  for (int i = 0; i < kPoints; ++i) {
    const Vector6<S> eta = rng.pose<S>(1.3);
    const Vector6<S> nu = rng.velocity<S>();
    const Vector6<S> v = rng.vec6<S>(-2, 2);
    const auto k = EulerKinematics<S>::from_pose(eta);
    ASSERT_EQ(k.status(), Status::ok);
    Matrix6<S> j, j_inv, j_dot;
    ASSERT_EQ(jacobian(eta, j), Status::ok);
    ASSERT_EQ(jacobian_inverse(eta, j_inv), Status::ok);
    ASSERT_EQ(jacobian_dot(eta, nu, j_dot), Status::ok);
    EXPECT_TRUE(all_near(k.jacobian(), j, 0.0));
    EXPECT_TRUE(all_near(k.jacobian_inverse(), j_inv, 0.0));
    EXPECT_TRUE(all_near(k.jacobian_dot(nu), j_dot, 0.0));
    // Block products round differently from the 6x6 ones only in summation order.
    const double tol = 16 * eps<S>() * (1.0 + max_abs(j)) * (1.0 + max_abs(nu));
    EXPECT_TRUE(all_near(k.apply(v), j * v, tol)) << "at point " << i;
    EXPECT_TRUE(all_near(k.apply_inverse(v), j_inv * v, tol)) << "at point " << i;
    EXPECT_TRUE(all_near(k.apply_transpose(v), j.transpose() * v, tol)) << "at point " << i;
    const double tol_dot = 16 * eps<S>() * (1.0 + max_abs(j_dot)) * (1.0 + max_abs(v));
    EXPECT_TRUE(all_near(k.apply_dot(nu, v), j_dot * v, tol_dot)) << "at point " << i;
  }
}

}  // namespace
