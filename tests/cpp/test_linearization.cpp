// Analytic Jacobians of the 12-state plant (model/linearization.hpp) against
// central finite differences of Vehicle::derivative() at random states, for
// NEROV, the BlueROV2 Heavy and random vehicles that use every term, in both
// Coriolis forms, with and without a current; and against values worked out
// by hand for NEROV at rest.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "neurov/model/linearization.hpp"
#include "neurov/model/vehicle.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::max_abs;
using neurov_test::Rng;
using Vec3 = Vector3<double>;
using Vec6 = Vector6<double>;
using Mat12 = Matrix12<double>;
using Mat12x6 = Matrix12x6<double>;

constexpr CoriolisForm kForms[] = {CoriolisForm::velocity_independent, CoriolisForm::kirchhoff};

template <typename S>
Vehicle<S> make(const VehicleParameters<S>& p) {
  Vehicle<S> v;
  const ValidationError e = Vehicle<S>::create(p, v);
  EXPECT_TRUE(e.ok()) << (e.field ? e.field : "");
  return v;
}

/// The numbers of python/neurov/vehicles/bluerov2_heavy.toml (von Benzon et
/// al. 2022, Table A1), which the C++ library has no reader for.
VehicleParameters<double> bluerov2_heavy_parameters(CoriolisForm form) {
  VehicleParameters<double> p;
  p.mass = 13.5;
  p.inertia = Vec3(0.26, 0.23, 0.37).asDiagonal();
  p.centre_of_buoyancy = Vec3(0.0, 0.0, -0.01);
  p.weight = 132.435;
  p.buoyancy = 131.454;
  Vec6 added;
  added << 6.3567, 7.1206, 18.6863, 0.1858, 0.1348, 0.2215;
  p.added_mass = added.asDiagonal();
  p.linear_damping << 13.7, 0.0, 33.0, 0.0, 0.8, 0.0;
  p.quadratic_damping << 141.0, 217.0, 190.0, 1.192, 0.470, 1.500;
  p.coriolis_form = form;
  return p;
}

VehicleParameters<double> nerov_in(CoriolisForm form) {
  auto p = nerov_parameters<double>();
  p.coriolis_form = form;
  return p;
}

using State12 = Eigen::Matrix<double, 12, 1>;

State12 plant_derivative(const Vehicle<double>& v, const State12& x, const Vec6& tau,
                         const Vec3& current) {
  Vec6 eta_dot, nu_dot;
  const Status s = v.derivative(x.head<6>(), x.tail<6>(), tau, current, eta_dot, nu_dot);
  EXPECT_EQ(s, Status::ok);
  State12 f;
  f << eta_dot, nu_dot;
  return f;
}

/// Central differences of f at x, column j along x_j, with a step scaled to
/// each coordinate: truncation error ~ h^2, rounding ~ epsilon / h, both far
/// below 1e-6 at h ~ 1e-5.
template <typename Vec, typename F, typename Jacobian>
void central_difference(const Vec& x, const F& f, Jacobian& d) {
  for (int j = 0; j < x.size(); ++j) {
    const double h = 1e-5 * std::max(1.0, std::abs(x(j)));
    Vec xp = x, xm = x;
    xp(j) += h;
    xm(j) -= h;
    d.col(j) = (f(xp) - f(xm)) / (2.0 * h);
  }
}

void finite_difference(const Vehicle<double>& v, const State12& x, const Vec6& tau,
                       const Vec3& current, Mat12& a, Mat12x6& b) {
  central_difference(x, [&](const State12& y) { return plant_derivative(v, y, tau, current); }, a);
  central_difference(tau, [&](const Vec6& t) { return plant_derivative(v, x, t, current); }, b);
}

/// Relative agreement of analytic and finite-difference Jacobians, entry by
/// entry, scaled by the largest entry of the row (rows mix N, m, rad/s).
::testing::AssertionResult rows_agree(const Eigen::MatrixXd& analytic,
                                      const Eigen::MatrixXd& numeric, double rel) {
  for (Eigen::Index i = 0; i < analytic.rows(); ++i) {
    const double scale = std::max(numeric.row(i).cwiseAbs().maxCoeff(), 1e-12);
    const double err = (analytic.row(i) - numeric.row(i)).cwiseAbs().maxCoeff();
    if (err > rel * scale)
      return ::testing::AssertionFailure()
             << "row " << i << ": max error " << err << " > " << rel << " * " << scale
             << "\nanalytic " << analytic.row(i) << "\nnumeric  " << numeric.row(i);
  }
  return ::testing::AssertionSuccess();
}

void check_against_finite_differences(const VehicleParameters<double>& p, std::uint32_t seed,
                                      bool with_current) {
  const Vehicle<double> v = make(p);
  Rng rng(seed);
  for (int k = 0; k < 50; ++k) {
    State12 x;
    x << rng.pose<double>(1.2), rng.velocity<double>();
    const Vec6 tau = rng.vec6<double>(-200.0, 200.0);
    const Vec3 current = with_current ? rng.vec3<double>(-1.0, 1.0) : Vec3::Zero();
    Mat12 a, a_fd;
    Mat12x6 b, b_fd;
    ASSERT_EQ(linearize(v, Vec6(x.head<6>()), Vec6(x.tail<6>()), tau, current, a, b), Status::ok);
    finite_difference(v, x, tau, current, a_fd, b_fd);
    ASSERT_TRUE(rows_agree(a, a_fd, 1e-6)) << "A at point " << k << ", x = " << x.transpose();
    ASSERT_TRUE(rows_agree(b, b_fd, 1e-6)) << "B at point " << k;
  }
}

TEST(Linearization, NerovMatchesFiniteDifferencesInBothForms) {
  for (const CoriolisForm form : kForms) {
    SCOPED_TRACE(static_cast<int>(form));
    check_against_finite_differences(nerov_in(form), 11, false);
    check_against_finite_differences(nerov_in(form), 12, true);
  }
}

TEST(Linearization, BlueRov2MatchesFiniteDifferencesInBothForms) {
  for (const CoriolisForm form : kForms) {
    SCOPED_TRACE(static_cast<int>(form));
    check_against_finite_differences(bluerov2_heavy_parameters(form), 21, false);
    check_against_finite_differences(bluerov2_heavy_parameters(form), 22, true);
  }
}

// r_g != 0, full M_A and W != B: the terms NEROV and the BlueROV2 leave at
// zero, and Vehicle's general (non-diagonal) path.
TEST(Linearization, RandomVehiclesMatchFiniteDifferencesInBothForms) {
  Rng rng(31);
  for (const CoriolisForm form : kForms) {
    for (int i = 0; i < 5; ++i) {
      SCOPED_TRACE(i);
      const auto p = neurov_test::random_vehicle_parameters<double>(rng, form);
      check_against_finite_differences(p, 40 + i, i % 2 == 1);
    }
  }
}

TEST(Linearization, CoriolisFormDoesNotChangeTheJacobian) {
  Rng rng(5);
  const auto p = neurov_test::random_vehicle_parameters<double>(rng, CoriolisForm::kirchhoff);
  auto q = p;
  q.coriolis_form = CoriolisForm::velocity_independent;
  const Vehicle<double> vk = make(p), vi = make(q);
  const Vec6 eta = rng.pose<double>(), nu = rng.velocity<double>(), tau = Vec6::Zero();
  const Vec3 c = rng.vec3<double>(-1.0, 1.0);
  Mat12 ak, ai;
  Mat12x6 bk, bi;
  ASSERT_EQ(linearize(vk, eta, nu, tau, c, ak, bk), Status::ok);
  ASSERT_EQ(linearize(vi, eta, nu, tau, c, ai, bi), Status::ok);
  EXPECT_EQ(ak, ai);
  EXPECT_EQ(bk, bi);
}

// NEROV at rest: J(0) = I; g only through the 0.02 m metacentric height,
// dK/dphi = dM/dtheta = B * 0.02 = 36 N m; D(0) = D_L; M = diag(m + M_A).
TEST(Linearization, NerovAtRestByHand) {
  const Vehicle<double> v = make(nerov_parameters<double>());
  Mat12 a;
  Mat12x6 b;
  ASSERT_EQ(linearize(v, Vec6::Zero(), Vec6::Zero(), Vec6::Zero(), Vec3::Zero(), a, b),
            Status::ok);
  Mat12 a_hand = Mat12::Zero();
  a_hand.topRightCorner<6, 6>().setIdentity();
  a_hand(9, 3) = -36.0 / (25.0 + 15.0);
  a_hand(10, 4) = -36.0 / (50.0 + 30.0);
  const double mass[6] = {215.0, 265.0, 265.0, 40.0, 80.0, 80.0};
  const double damping[6] = {70.0, 100.0, 100.0, 30.0, 50.0, 50.0};
  Mat12x6 b_hand = Mat12x6::Zero();
  for (int i = 0; i < 6; ++i) {
    a_hand(6 + i, 6 + i) = -damping[i] / mass[i];
    b_hand(6 + i, i) = 1.0 / mass[i];
  }
  EXPECT_LE((a - a_hand).cwiseAbs().maxCoeff(), 1e-12 * max_abs(a_hand)) << a;
  EXPECT_LE((b - b_hand).cwiseAbs().maxCoeff(), 1e-12 * max_abs(b_hand)) << b;
}

TEST(Linearization, FloatAgreesWithDouble) {
  Rng rng(7);
  const auto p = neurov_test::random_vehicle_parameters<double>(rng, CoriolisForm::kirchhoff);
  const Vehicle<double> vd = make(p);
  const Vehicle<float> vf = make(p.cast<float>());
  const Vec6 eta = rng.pose<double>(1.0), nu = rng.velocity<double>(), tau = Vec6::Zero();
  const Vec3 c = rng.vec3<double>(-1.0, 1.0);
  Mat12 ad;
  Mat12x6 bd;
  Matrix12<float> af;
  Matrix12x6<float> bf;
  ASSERT_EQ(linearize(vd, eta, nu, tau, c, ad, bd), Status::ok);
  ASSERT_EQ(linearize(vf, Vector6<float>(eta.cast<float>()), Vector6<float>(nu.cast<float>()),
                      Vector6<float>(tau.cast<float>()), Vector3<float>(c.cast<float>()), af, bf),
            Status::ok);
  EXPECT_TRUE(rows_agree(af.cast<double>(), ad, 1e-4));
  EXPECT_TRUE(rows_agree(bf.cast<double>(), bd, 1e-4));
}

TEST(Linearization, StatusesAndZeroedOutputs) {
  const Vehicle<double> nerov = make(nerov_parameters<double>());
  Mat12 a = Mat12::Constant(1.0);
  Mat12x6 b = Mat12x6::Constant(1.0);
  EXPECT_EQ(linearize(Vehicle<double>(), Vec6::Zero(), Vec6::Zero(), Vec6::Zero(), Vec3::Zero(),
                      a, b),
            Status::invalid_argument);
  EXPECT_TRUE(a.isZero(0.0) && b.isZero(0.0));

  Vec6 nu = Vec6::Zero();
  nu(2) = std::numeric_limits<double>::quiet_NaN();
  a.setConstant(1.0);
  EXPECT_EQ(linearize(nerov, Vec6::Zero(), nu, Vec6::Zero(), Vec3::Zero(), a, b),
            Status::non_finite_input);
  EXPECT_TRUE(a.isZero(0.0) && b.isZero(0.0));

  Vec6 eta = Vec6::Zero();
  eta(4) = neurov_test::kPi / 2;
  EXPECT_EQ(linearize(nerov, eta, Vec6::Ones(), Vec6::Zero(), Vec3::Zero(), a, b),
            Status::near_singularity);
  EXPECT_TRUE(a.allFinite() && b.allFinite());
}

}  // namespace
