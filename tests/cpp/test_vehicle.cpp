// Vehicle model M nu_dot + C(nu) nu + D(nu) nu + g(eta) = tau: the NEROV
// numbers against the paper written out literally, the structural properties
// (M SPD, C skew) on random vehicles that use every term, validation, and the
// non-finite / empty-vehicle contracts of the hot path.
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <gtest/gtest.h>

#include "neurov/model/vehicle.hpp"
#include "nerov_paper.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using namespace neurov_test;

NEUROV_SCALAR_SUITE(VehicleTest);

constexpr CoriolisForm kForms[] = {CoriolisForm::velocity_independent, CoriolisForm::kirchhoff};

const char* form_name(CoriolisForm f) {
  return f == CoriolisForm::kirchhoff ? "kirchhoff" : "velocity_independent";
}

/// Fossen's g(eta) (2011, eq. 4.6), written out here rather than taken from
/// the header so the two are independent.
Eigen::Matrix<double, 6, 1> fossen_restoring(double W, double B, const Eigen::Vector3d& rg,
                                             const Eigen::Vector3d& rb, double phi, double theta) {
  const double sph = std::sin(phi), cph = std::cos(phi), sth = std::sin(theta),
               cth = std::cos(theta);
  const double xg = rg.x(), yg = rg.y(), zg = rg.z(), xb = rb.x(), yb = rb.y(), zb = rb.z();
  Eigen::Matrix<double, 6, 1> g;
  g << (W - B) * sth,                                                      //
      -(W - B) * cth * sph,                                                //
      -(W - B) * cth * cph,                                                //
      -(yg * W - yb * B) * cth * cph + (zg * W - zb * B) * cth * sph,      //
      (zg * W - zb * B) * sth + (xg * W - xb * B) * cth * cph,             //
      -(xg * W - xb * B) * cth * sph - (yg * W - yb * B) * sth;
  return g;
}

/// M = M_RB + M_A from the parameters, built independently of the header.
template <typename S>
Eigen::Matrix<double, 6, 6> mass_matrix_of(const VehicleParameters<S>& p) {
  const Eigen::Vector3d rg = p.centre_of_gravity.template cast<double>();
  Eigen::Matrix3d s;
  s << 0, -rg.z(), rg.y(), rg.z(), 0, -rg.x(), -rg.y(), rg.x(), 0;
  const double m = double(p.mass);
  Eigen::Matrix<double, 6, 6> mrb;
  mrb << m * Eigen::Matrix3d::Identity(), -m * s, m * s, p.inertia.template cast<double>();
  return mrb + p.added_mass.template cast<double>();
}

// ---------------------------------------------------------------- mass matrix

TYPED_TEST(VehicleTest, NerovMassMatrixIsThePapersDiagonal) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  Vector6<S> diag;
  diag << 215, 265, 265, 40, 80, 80;
  EXPECT_TRUE(all_near(v.mass_matrix(), Matrix6<S>(diag.asDiagonal()), 0.0));
  EXPECT_EQ(Eigen::LLT<Matrix6<S>>(v.mass_matrix()).info(), Eigen::Success);
  EXPECT_TRUE(all_near(v.mass_matrix_inverse() * v.mass_matrix(), Matrix6<S>::Identity(),
                       4 * eps<S>()));
}

TYPED_TEST(VehicleTest, MassMatrixIsSymmetricPositiveDefiniteForRandomVehicles) {
  using S = TypeParam;
  Rng rng(21);
  for (int i = 0; i < 50; ++i) {
    const auto p = neurov_test::random_vehicle_parameters<S>(rng, CoriolisForm::kirchhoff);
    const Vehicle<S> v = make_vehicle(p);
    const Matrix6<S>& m = v.mass_matrix();
    EXPECT_TRUE(all_near(m, m.transpose(), 0.0));
    EXPECT_EQ(Eigen::LLT<Matrix6<S>>(m).info(), Eigen::Success);
    const auto expected = mass_matrix_of(p);
    EXPECT_TRUE(all_near(m, expected, 8 * eps<S>() * max_abs(expected)));
    EXPECT_TRUE(all_near(v.mass_matrix_inverse() * m, Matrix6<S>::Identity(), 512 * eps<S>()));
  }
}

// ------------------------------------------------------------------- Coriolis

/// NEROV and a random vehicle in each Coriolis form, each at kPoints random
/// body velocities: check(vehicle, nu, i).
template <typename S, typename Check>
void at_random_velocities_in_both_forms(Rng& rng, Check check) {
  for (const CoriolisForm form : kForms) {
    SCOPED_TRACE(form_name(form));
    auto nerov = nerov_parameters<S>();
    nerov.coriolis_form = form;
    const Vehicle<S> vehicles[] = {make_vehicle(nerov),
                                   make_vehicle(random_vehicle_parameters<S>(rng, form))};
    for (const Vehicle<S>& v : vehicles)
      for (int i = 0; i < kPoints; ++i) check(v, rng.velocity<S>(), i);
  }
}

TYPED_TEST(VehicleTest, CoriolisIsSkewSymmetricInBothForms) {
  using S = TypeParam;
  Rng rng(22);
  at_random_velocities_in_both_forms<S>(rng, [](const Vehicle<S>& v, const Vector6<S>& nu, int i) {
    const Matrix6<S> c = v.coriolis(nu);
    const double scale = max_abs(c);
    EXPECT_TRUE(all_near(c, Matrix6<S>(-c.transpose()), 8 * eps<S>() * scale)) << "at point " << i;
    // Skew-symmetry is what makes C do no work: nu^T C nu = 0.
    EXPECT_NEAR(double(nu.dot(c * nu)), 0.0, 64 * eps<S>() * scale * nu.squaredNorm())
        << "at point " << i;
    EXPECT_TRUE(
        all_near(c, Matrix6<S>(v.coriolis_rigid_body(nu) + v.coriolis_added_mass(nu)), 0.0));
  });
}

TYPED_TEST(VehicleTest, BothCoriolisFormsGiveTheSameForce) {
  using S = TypeParam;
  Rng rng(23);
  for (int k = 0; k < 5; ++k) {
    const auto p = neurov_test::random_vehicle_parameters<S>(rng, CoriolisForm::kirchhoff);
    auto q = p;
    q.coriolis_form = CoriolisForm::velocity_independent;
    const Vehicle<S> kirchhoff = make_vehicle(p), independent = make_vehicle(q);
    for (int i = 0; i < kPoints / 5; ++i) {
      const Vector6<S> nu = rng.velocity<S>();
      const Matrix6<S> ck = kirchhoff.coriolis(nu), ci = independent.coriolis(nu);
      const double tol = 64 * eps<S>() * (max_abs(ck) + max_abs(ci));
      EXPECT_TRUE(all_near(ck * nu, ci * nu, tol)) << "at point " << i;
      // The forms are genuinely different matrices; only C(nu) nu agrees.
      EXPECT_GT(max_abs(ck - ci), 1e-3);
    }
  }
}

TYPED_TEST(VehicleTest, CoriolisForceEqualsCoriolisMatrixTimesVelocity) {
  using S = TypeParam;
  Rng rng(24);
  at_random_velocities_in_both_forms<S>(rng, [](const Vehicle<S>& v, const Vector6<S>& nu, int i) {
    const Matrix6<S> c = v.coriolis(nu);
    EXPECT_TRUE(all_near(v.coriolis_force(nu), c * nu, 64 * eps<S>() * max_abs(c)))
        << "at point " << i;
  });
}

// The paper's eq. 39 (nerov_paper.hpp) in both Coriolis forms.
TYPED_TEST(VehicleTest, NerovCoriolisIsThePapersEquation39) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  auto pk = nerov_parameters<S>();
  pk.coriolis_form = CoriolisForm::kirchhoff;
  const Vehicle<S> vk = make_vehicle(pk);
  Rng rng(25);
  for (int i = 0; i < kPoints; ++i) {
    const Vector6<S> nu = rng.velocity<S>();
    const Eigen::Matrix<double, 6, 6> c = nerov_paper::nerov_c_eq39(nu.template cast<double>());
    const double tol = 4 * eps<S>() * max_abs(c);
    EXPECT_TRUE(all_near(v.coriolis(nu), c, tol)) << "at point " << i;
    // The kirchhoff form is another matrix with the same product.
    EXPECT_TRUE(all_near(vk.coriolis(nu) * nu, c * nu.template cast<double>(), 16 * tol))
        << "at point " << i;
  }
}

// ------------------------------------------------------ damping and restoring

TYPED_TEST(VehicleTest, NerovDampingIsThePapersDiagonal) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  Rng rng(26);
  for (int i = 0; i < kPoints; ++i) {
    const Vector6<S> nu = rng.vec6<S>(-2, 2);
    const Eigen::Matrix<double, 6, 1> d =
        nerov_paper::nerov_d(nu.template cast<double>()).diagonal();
    const Matrix6<S> dm = v.damping(nu);
    EXPECT_TRUE(all_near(dm, Eigen::Matrix<double, 6, 6>(d.asDiagonal()), 4 * eps<S>() * 500))
        << "at point " << i;
    EXPECT_TRUE(all_near(v.damping_diagonal(nu), d, 4 * eps<S>() * 500));
  }
}

TYPED_TEST(VehicleTest, NerovRestoringIsThePapersPendulum) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  Rng rng(27);
  for (int i = 0; i < kPoints; ++i) {
    const Vector6<S> eta = rng.pose<S>(neurov_test::kPi / 2);
    const Eigen::Matrix<double, 6, 1> g = nerov_paper::nerov_g(eta.template cast<double>());
    EXPECT_TRUE(all_near(v.restoring(eta), g, 64 * eps<S>() * 36)) << "at point " << i;
  }
}

TYPED_TEST(VehicleTest, RestoringMatchesFossensGeneralFormula) {
  using S = TypeParam;
  Rng rng(28);
  for (int k = 0; k < 10; ++k) {
    const auto p = neurov_test::random_vehicle_parameters<S>(rng, CoriolisForm::kirchhoff);
    ASSERT_NE(p.weight, p.buoyancy);
    ASSERT_FALSE(p.centre_of_gravity.isZero(S(0)));
    ASSERT_FALSE(p.centre_of_buoyancy.isZero(S(0)));
    const Vehicle<S> v = make_vehicle(p);
    const double scale = double(std::max(p.weight, p.buoyancy));
    for (int i = 0; i < kPoints / 10; ++i) {
      const Vector6<S> eta = rng.pose<S>(neurov_test::kPi / 2);
      const auto g = fossen_restoring(p.weight, p.buoyancy, p.centre_of_gravity.template cast<double>(),
                                      p.centre_of_buoyancy.template cast<double>(), eta(3), eta(4));
      EXPECT_TRUE(all_near(v.restoring(eta), g, 64 * eps<S>() * scale)) << "at point " << i;
    }
  }
}

// ---------------------------------------------------------------- acceleration


/// tau - C(nu) nu - D(nu) nu - g(eta) in double: M nu_dot by the model's
/// formulas (C from the vehicle, tested above). `nu_double` is nu in double
/// when it was formed in double (a relative velocity).
template <typename S>
Eigen::Matrix<double, 6, 1> force_balance(const VehicleParameters<S>& p, const Vehicle<S>& v,
                                          const Vector6<S>& eta, const Vector6<S>& nu,
                                          const Vector6<S>& tau,
                                          const Eigen::Matrix<double, 6, 1>* nu_double = nullptr) {
  const Eigen::Matrix<double, 6, 1> nud =
      nu_double ? *nu_double : Eigen::Matrix<double, 6, 1>(nu.template cast<double>());
  const Eigen::Matrix<double, 6, 1> d =
      p.linear_damping.template cast<double>() +
      p.quadratic_damping.template cast<double>().cwiseProduct(nud.cwiseAbs());
  return tau.template cast<double>() - v.coriolis(nu).template cast<double>() * nud -
         d.cwiseProduct(nud) -
         fossen_restoring(p.weight, p.buoyancy, p.centre_of_gravity.template cast<double>(),
                          p.centre_of_buoyancy.template cast<double>(), eta(3), eta(4));
}

TYPED_TEST(VehicleTest, AccelerationSolvesTheEquationOfMotion) {
  using S = TypeParam;
  Rng rng(29);
  std::vector<VehicleParameters<S>> params{nerov_parameters<S>()};
  for (const CoriolisForm form : kForms)
    for (int k = 0; k < 2; ++k) params.push_back(neurov_test::random_vehicle_parameters<S>(rng, form));
  for (const auto& p : params) {
    const Vehicle<S> v = make_vehicle(p);
    // A general (pivoted QR) solve, so nothing relies on M being SPD or on M^-1.
    const auto qr = mass_matrix_of(p).colPivHouseholderQr();
    for (int i = 0; i < kPoints / 5; ++i) {
      const Vector6<S> eta = rng.pose<S>(1.3), nu = rng.velocity<S>(), tau = rng.vec6<S>(-200, 200);
      const Eigen::Matrix<double, 6, 1> rhs = force_balance(p, v, eta, nu, tau);
      const Eigen::Matrix<double, 6, 1> expected = qr.solve(rhs);
      Vector6<S> nu_dot;
      ASSERT_EQ(v.acceleration(eta, nu, tau, nu_dot), Status::ok);
      const double tol = 256 * eps<S>() * (max_abs(expected) + max_abs(rhs));
      EXPECT_TRUE(all_near(nu_dot, expected, tol)) << "at point " << i;
      // A zero current is no current, and derivative() agrees with both.
      Vector6<S> nu_dot_c, eta_dot, nu_dot_d;
      ASSERT_EQ(v.acceleration(eta, nu, tau, Vector3<S>::Zero(), nu_dot_c), Status::ok);
      EXPECT_TRUE(all_near(nu_dot_c, nu_dot, tol));
      ASSERT_EQ(v.derivative(eta, nu, tau, Vector3<S>::Zero(), eta_dot, nu_dot_d), Status::ok);
      EXPECT_TRUE(all_near(nu_dot_d, nu_dot, tol));
      Matrix6<S> j;
      jacobian(eta, j);
      EXPECT_TRUE(all_near(eta_dot, j * nu, 64 * eps<S>() * 10));
    }
  }
}

// With a current the model runs on nu_r = nu - [R^T V_c; 0] and adds the
// turning of the current seen from the body, nu_c_dot = [-w x v_c; 0].
TYPED_TEST(VehicleTest, AccelerationInCurrentUsesRelativeVelocity) {
  using S = TypeParam;
  Rng rng(30);
  for (const CoriolisForm form : kForms) {
    const auto p = neurov_test::random_vehicle_parameters<S>(rng, form);
    const Vehicle<S> v = make_vehicle(p);
    const auto qr = mass_matrix_of(p).colPivHouseholderQr();
    for (int i = 0; i < kPoints / 2; ++i) {
      Vector6<S> eta = rng.pose<S>(1.3);
      const Vector6<S> nu = rng.velocity<S>(), tau = rng.vec6<S>(-200, 200);
      const Vector3<S> current = rng.vec3<S>(-1, 1);
      // At pitch +-90 deg nu_dot must still use the true R and g, not the
      // clamped cosine that only T needs.
      if (i < 4) eta(4) = S(i % 2 ? neurov_test::kPi / 2 : -neurov_test::kPi / 2);
      const Eigen::Matrix3d r = rotation<double>(eta(3), eta(4), eta(5));
      const Eigen::Vector3d vc = r.transpose() * current.template cast<double>();
      Eigen::Matrix<double, 6, 1> nu_r = nu.template cast<double>();
      nu_r.head<3>() -= vc;
      const Vector6<S> nu_r_s = nu_r.cast<S>();
      const Eigen::Matrix<double, 6, 1> rhs = force_balance(p, v, eta, nu_r_s, tau, &nu_r);
      Eigen::Matrix<double, 6, 1> expected = qr.solve(rhs);
      const Eigen::Vector3d w = nu.template tail<3>().template cast<double>();
      expected.head<3>() -= w.cross(vc);
      Vector6<S> nu_dot;
      ASSERT_EQ(v.acceleration(eta, nu, tau, current, nu_dot), Status::ok);
      const double tol = 512 * eps<S>() * (max_abs(expected) + max_abs(rhs));
      EXPECT_TRUE(all_near(nu_dot, expected, tol)) << form_name(form) << " at point " << i;
    }
  }
}

TYPED_TEST(VehicleTest, VehicleAtRestIsPushedTowardTheCurrent) {
  using S = TypeParam;
  const auto p = neurov_test::nerov_without_restoring<S>();
  const Vehicle<S> v = make_vehicle(p);
  Rng rng(31);
  for (int i = 0; i < kPoints; ++i) {
    const Vector6<S> eta = rng.pose<S>(1.3);
    const Vector3<S> current = rng.vec3<S>(-1, 1);
    Vector6<S> nu_dot;
    ASSERT_EQ(v.acceleration(eta, Vector6<S>::Zero(), Vector6<S>::Zero(), current, nu_dot),
              Status::ok);
    const Vector3<S> vc = rotation<S>(eta(3), eta(4), eta(5)).transpose() * current;
    const Vector3<S> a = nu_dot.template head<3>();
    EXPECT_GT(double(a.dot(vc)), 0.0) << "at point " << i;
    // M and D are diagonal for NEROV: each axis is dragged on its own, by
    // (d_l + d_q |v_c|) v_c / m_ii, so nu_dot is the current scaled per axis.
    for (int k = 0; k < 3; ++k) {
      const double vck = vc(k);
      const double expected = (double(p.linear_damping(k)) +
                               double(p.quadratic_damping(k)) * std::abs(vck)) *
                              vck / double(v.mass_matrix()(k, k));
      EXPECT_NEAR(double(a(k)), expected, 64 * eps<S>() * (1 + std::abs(expected)))
          << "axis " << k << " at point " << i;
    }
  }
  // Along a body axis the push is exactly along that axis.
  Vector6<S> nu_dot;
  ASSERT_EQ(v.acceleration(Vector6<S>::Zero(), Vector6<S>::Zero(), Vector6<S>::Zero(),
                           Vector3<S>(S(0.5), S(0), S(0)), nu_dot),
            Status::ok);
  EXPECT_GT(nu_dot(0), S(0));
  EXPECT_TRUE(nu_dot.template tail<5>().isZero(S(0)));
}

// acceleration(..., current) reports ok at pitch +-90 deg because nu_dot needs
// no 1/cos(theta); so neither g(eta) nor the current's rotation may use the
// clamped cosine. (An earlier header did: roll acceleration was off by
// 36 * threshold / 40, 1.5e-4 rad/s^2 in float.)
TYPED_TEST(VehicleTest, AccelerationAtNinetyDegreesPitchIgnoresTheClamp) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  Vector6<S> nu, tau;
  nu << S(0.3), S(-0.2), S(0.1), S(0.2), S(0.1), S(-0.3);
  tau << S(10), S(-5), S(3), S(1), S(-2), S(0.5);
  for (const S theta : {S(neurov_test::kPi / 2), S(-neurov_test::kPi / 2)}) {
    Vector6<S> eta;
    eta << S(0), S(0), S(0), S(0.5), theta, S(0.2);
    Vector6<S> plain, with_zero_current;
    ASSERT_EQ(v.acceleration(eta, nu, tau, plain), Status::ok);
    ASSERT_EQ(v.acceleration(eta, nu, tau, Vector3<S>::Zero(), with_zero_current), Status::ok);
    EXPECT_TRUE(all_near(with_zero_current, plain, 64 * eps<S>() * (1 + max_abs(plain))))
        << "theta = " << theta;
  }
}

// ------------------------------------------------------------------ validation

struct BadField {
  const char* what;
  std::function<void(VehicleParameters<double>&)> mutate;
  const char* field;
  int index;
};

std::vector<BadField> bad_fields() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  return {
      {"zero mass", [](auto& p) { p.mass = 0; }, "mass", -1},
      {"negative mass", [](auto& p) { p.mass = -5; }, "mass", -1},
      {"NaN mass", [=](auto& p) { p.mass = nan; }, "mass", -1},
      {"NaN inertia", [=](auto& p) { p.inertia(1, 1) = nan; }, "inertia", 4},
      {"Inf inertia", [=](auto& p) { p.inertia(0, 0) = inf; }, "inertia", 0},
      {"NaN centre_of_gravity", [=](auto& p) { p.centre_of_gravity(2) = nan; },
       "centre_of_gravity", 2},
      {"Inf centre_of_buoyancy", [=](auto& p) { p.centre_of_buoyancy(0) = -inf; },
       "centre_of_buoyancy", 0},
      {"negative weight", [](auto& p) { p.weight = -1; }, "weight", -1},
      {"Inf weight", [=](auto& p) { p.weight = inf; }, "weight", -1},
      {"negative buoyancy", [](auto& p) { p.buoyancy = -1; }, "buoyancy", -1},
      {"NaN added_mass", [=](auto& p) { p.added_mass(3, 3) = nan; }, "added_mass", 21},
      {"negative linear damping", [](auto& p) { p.linear_damping(2) = -1; }, "linear_damping", 2},
      {"NaN linear damping", [=](auto& p) { p.linear_damping(0) = nan; }, "linear_damping", 0},
      {"negative quadratic damping", [](auto& p) { p.quadratic_damping(5) = -0.5; },
       "quadratic_damping", 5},
      {"unknown coriolis form",
       [](auto& p) { p.coriolis_form = static_cast<CoriolisForm>(7); }, "coriolis_form", -1},
      // Symmetry errors report the first upper-triangle pair, row-major i*cols + j.
      {"non-symmetric inertia", [](auto& p) { p.inertia(0, 1) = 1; }, "inertia", 1},
      {"non-symmetric inertia (lower)", [](auto& p) { p.inertia(2, 1) = 2; }, "inertia", 5},
      {"non-symmetric added mass", [](auto& p) { p.added_mass(1, 4) = 5; }, "added_mass", 10},
      // Each part must be physical on its own, so a negative entry is blamed on
      // its field even where the rest of M would hide it.
      {"indefinite added mass", [](auto& p) { p.added_mass(0, 0) = -500; }, "added_mass", -1},
      {"indefinite added mass hidden in M", [](auto& p) { p.added_mass(0, 0) = -10; },
       "added_mass", -1},
      {"indefinite inertia", [](auto& p) { p.inertia(2, 2) = -60; }, "inertia", -1},
      {"indefinite inertia hidden in M", [](auto& p) { p.inertia(2, 2) = -10; }, "inertia", -1},
      // A centre of gravity 1 m off the origin with NEROV's inertia breaks the
      // parallel-axis bound, so M_RB + M_A is indefinite though every entry is fine.
      {"indefinite from centre of gravity", [](auto& p) { p.centre_of_gravity.z() = 1; },
       "mass_matrix", -1},
  };
}

TYPED_TEST(VehicleTest, ValidationNamesTheBadField) {
  using S = TypeParam;
  EXPECT_TRUE(validate(nerov_parameters<S>()).ok());
  EXPECT_EQ(validate(nerov_parameters<S>()).field, nullptr);
  for (const BadField& bad : bad_fields()) {
    SCOPED_TRACE(bad.what);
    auto pd = nerov_parameters<double>();
    bad.mutate(pd);
    const VehicleParameters<S> p = pd.template cast<S>();
    const ValidationError e = validate(p);
    ASSERT_FALSE(e.ok());
    ASSERT_TRUE(static_cast<bool>(e));
    ASSERT_NE(e.field, nullptr);
    EXPECT_STREQ(e.field, bad.field);
    EXPECT_EQ(e.index, bad.index);
    EXPECT_NE(e.expected, nullptr);
    char buf[256];
    e.format(buf, sizeof buf);
    EXPECT_NE(std::string(buf).find(bad.field), std::string::npos) << buf;
  }
}

TYPED_TEST(VehicleTest, ValidationReportsTheOffendingValue) {
  using S = TypeParam;
  auto p = nerov_parameters<S>();
  p.linear_damping(3) = S(-2.5);
  EXPECT_EQ(validate(p).value, -2.5);
  p = nerov_parameters<S>();
  p.added_mass(1, 4) = S(5);
  EXPECT_EQ(validate(p).value, 5.0);  // M[i,j] - M[j,i]
  p = nerov_parameters<S>();
  p.mass = S(-1);
  EXPECT_EQ(validate(p).value, -1.0);
  // Zero damping, zero weight and buoyancy are allowed: >= 0, not > 0.
  p = nerov_parameters<S>();
  p.linear_damping.setZero();
  p.quadratic_damping.setZero();
  p.weight = p.buoyancy = S(0);
  EXPECT_TRUE(validate(p).ok());
}

// Every matrix check reports entry (i, j) at the row-major index i * cols + j
// (numpy's flat index), whatever the check and Eigen's storage order:
// inertia(0,1) is index 1 both when NaN and when asymmetric, added_mass(1,4)
// is 10 both when Inf and when asymmetric.
TYPED_TEST(VehicleTest, MatrixEntryIndexIsRowMajorInEveryCheck) {
  using S = TypeParam;
  auto p = nerov_parameters<S>();
  p.inertia(0, 1) = S(1);
  EXPECT_EQ(validate(p).index, 1);
  p.inertia(0, 1) = std::numeric_limits<S>::quiet_NaN();
  EXPECT_EQ(validate(p).index, 1);
  p = nerov_parameters<S>();
  p.added_mass(1, 4) = S(5);
  EXPECT_EQ(validate(p).index, 10);
  p.added_mass(1, 4) = std::numeric_limits<S>::infinity();
  EXPECT_EQ(validate(p).index, 10);
}

TYPED_TEST(VehicleTest, CreateLeavesOutUntouchedOnFailure) {
  using S = TypeParam;
  Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  const Matrix6<S> m_before = v.mass_matrix(), m_inv_before = v.mass_matrix_inverse();
  Vector6<S> eta, nu, tau;
  eta << 1, 2, 3, S(0.1), S(0.2), S(0.3);
  nu << S(0.5), S(-0.1), S(0.2), S(0.1), S(0.05), S(-0.2);
  tau << 10, 20, -30, 1, 2, 3;
  Vector6<S> before, after;
  ASSERT_EQ(v.acceleration(eta, nu, tau, before), Status::ok);
  for (const BadField& bad : bad_fields()) {
    SCOPED_TRACE(bad.what);
    auto pd = nerov_parameters<double>();
    bad.mutate(pd);
    EXPECT_FALSE(Vehicle<S>::create(pd.template cast<S>(), v).ok());
    EXPECT_TRUE(v.valid());
    EXPECT_EQ(v.parameters().mass, S(185));
    EXPECT_TRUE(v.parameters().linear_damping == nerov_parameters<S>().linear_damping);
    EXPECT_TRUE(v.mass_matrix() == m_before);
    EXPECT_TRUE(v.mass_matrix_inverse() == m_inv_before);
    ASSERT_EQ(v.acceleration(eta, nu, tau, after), Status::ok);
    EXPECT_EQ(std::memcmp(before.data(), after.data(), sizeof(S) * 6), 0);
  }
  Vehicle<S> empty;
  auto bad = nerov_parameters<S>();
  bad.mass = S(-1);
  EXPECT_FALSE(Vehicle<S>::create(bad, empty).ok());
  EXPECT_FALSE(empty.valid());
}

TYPED_TEST(VehicleTest, ThrowingConstructorNamesTheField) {
  using S = TypeParam;
  EXPECT_NO_THROW(Vehicle<S>{nerov_parameters<S>()});
  for (const BadField& bad : bad_fields()) {
    SCOPED_TRACE(bad.what);
    auto pd = nerov_parameters<double>();
    bad.mutate(pd);
    const VehicleParameters<S> p = pd.template cast<S>();
    try {
      Vehicle<S> v(p);
      ADD_FAILURE() << "no exception";
    } catch (const std::invalid_argument& ex) {
      EXPECT_NE(std::string(ex.what()).find(bad.field), std::string::npos) << ex.what();
    } catch (...) {
      ADD_FAILURE() << "threw something other than std::invalid_argument";
    }
  }
}

// --------------------------------------------------- non-finite and empty inputs

TYPED_TEST(VehicleTest, NonFiniteInputsGiveNonFiniteInputAndZeroAcceleration) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  const S bad_values[] = {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                          -std::numeric_limits<S>::infinity()};
  for (int which = 0; which < 3; ++which) {
    for (int k = 0; k < 6; ++k) {
      for (const S bad : bad_values) {
        SCOPED_TRACE(::testing::Message() << "input " << which << " entry " << k << " = " << bad);
        Vector6<S> in[3] = {Vector6<S>::Constant(S(0.1)), Vector6<S>::Constant(S(0.2)),
                            Vector6<S>::Constant(S(5))};
        in[which](k) = bad;
        Vector6<S> nu_dot = Vector6<S>::Constant(S(42)), eta_dot = nu_dot;
        EXPECT_EQ(v.acceleration(in[0], in[1], in[2], nu_dot), Status::non_finite_input);
        EXPECT_TRUE(nu_dot.isZero(S(0)));
        nu_dot.setConstant(S(42));
        EXPECT_EQ(v.acceleration(in[0], in[1], in[2], Vector3<S>(S(0.3), S(0), S(0)), nu_dot),
                  Status::non_finite_input);
        EXPECT_TRUE(nu_dot.isZero(S(0)));
        nu_dot.setConstant(S(42));
        EXPECT_EQ(v.derivative(in[0], in[1], in[2], Vector3<S>::Zero(), eta_dot, nu_dot),
                  Status::non_finite_input);
        EXPECT_TRUE(nu_dot.isZero(S(0)) && eta_dot.isZero(S(0)));
      }
    }
  }
  Vector6<S> nu_dot = Vector6<S>::Constant(S(42));
  const Vector3<S> bad_current(S(0), std::numeric_limits<S>::quiet_NaN(), S(0));
  EXPECT_EQ(v.acceleration(Vector6<S>::Zero(), Vector6<S>::Zero(), Vector6<S>::Zero(), bad_current,
                           nu_dot),
            Status::non_finite_input);
  EXPECT_TRUE(nu_dot.isZero(S(0)));
}

TYPED_TEST(VehicleTest, EmptyVehicleReturnsInvalidArgument) {
  using S = TypeParam;
  const Vehicle<S> v;
  EXPECT_FALSE(v.valid());
  const Vector6<S> x = Vector6<S>::Constant(S(0.1));
  Vector6<S> nu_dot = Vector6<S>::Constant(S(42)), eta_dot = nu_dot;
  EXPECT_EQ(v.acceleration(x, x, x, nu_dot), Status::invalid_argument);
  EXPECT_TRUE(nu_dot.isZero(S(0)));
  nu_dot.setConstant(S(42));
  EXPECT_EQ(v.acceleration(x, x, x, Vector3<S>::UnitX(), nu_dot), Status::invalid_argument);
  EXPECT_TRUE(nu_dot.isZero(S(0)));
  nu_dot.setConstant(S(42));
  EXPECT_EQ(v.derivative(x, x, x, Vector3<S>::Zero(), eta_dot, nu_dot), Status::invalid_argument);
  EXPECT_TRUE(nu_dot.isZero(S(0)) && eta_dot.isZero(S(0)));
}

TYPED_TEST(VehicleTest, OverflowGivesNonFiniteOutputAndZeroAcceleration) {
  using S = TypeParam;
  const Vehicle<S> v = make_vehicle(nerov_parameters<S>());
  // Finite, but C(nu) nu ~ m |nu|^2 overflows the scalar.
  const Vector6<S> huge = Vector6<S>::Constant(std::sqrt(std::numeric_limits<S>::max()));
  Vector6<S> nu_dot = Vector6<S>::Constant(S(42));
  EXPECT_EQ(v.acceleration(Vector6<S>::Zero(), huge, Vector6<S>::Zero(), nu_dot),
            Status::non_finite_output);
  EXPECT_TRUE(nu_dot.isZero(S(0)));
}

}  // namespace
