// Reference model (eq. 12-13): nu_d_dot = -Lambda_d nu_d + J^T(eta_d) Omega (r - eta_d),
// eta_d_dot = J(eta_d) nu_d. With every other DOF at zero, one DOF alone is
// exactly the linear second-order system x'' + lambda_d x' + omega (x - r) = 0
// (J is the identity on it), so its step response has a closed form to compare
// with. A general command must settle on r with the derivatives consistent.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "neurov/control/reference_model.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::eps;
using neurov_test::kPi;
using neurov_test::record;

NEUROV_SCALAR_SUITE(ReferenceModelTest);

/// x'' + lambda x' + omega (x - r) = 0 from rest at x0: position, velocity and
/// acceleration at t, for any damping ratio zeta = lambda / (2 sqrt(omega)).
struct SecondOrder {
  double lambda, omega, x0, r;

  double zeta() const { return lambda / (2 * std::sqrt(omega)); }

  void at(double t, double& x, double& v, double& a) const {
    const double wn = std::sqrt(omega), z = zeta(), step = r - x0;
    double e, de;  // x = x0 + step (1 - e), v = -step de
    if (std::abs(z - 1) < 1e-12) {
      e = std::exp(-wn * t) * (1 + wn * t);
      de = -wn * wn * t * std::exp(-wn * t);
    } else if (z < 1) {
      const double wd = wn * std::sqrt(1 - z * z);
      e = std::exp(-z * wn * t) * (std::cos(wd * t) + z * wn / wd * std::sin(wd * t));
      de = -std::exp(-z * wn * t) * wn * wn / wd * std::sin(wd * t);
    } else {
      const double s1 = -wn * (z - std::sqrt(z * z - 1)), s2 = -wn * (z + std::sqrt(z * z - 1));
      e = (s1 * std::exp(s2 * t) - s2 * std::exp(s1 * t)) / (s1 - s2);
      de = s1 * s2 * (std::exp(s2 * t) - std::exp(s1 * t)) / (s1 - s2);
    }
    x = x0 + step * (1 - e);
    v = -step * de;
    a = omega * (r - x) - lambda * v;
  }

  /// Peak overshoot as a fraction of the step: exp(-zeta pi / sqrt(1 - zeta^2)).
  double overshoot() const {
    const double z = zeta();
    return z < 1 ? std::exp(-z * kPi / std::sqrt(1 - z * z)) : 0.0;
  }
};

struct DofCase {
  int dof;
  double lambda, omega;
};

// Every DOF, with damping ratios 0.3, 0.7, 1 (critical) and 1.5.
const DofCase kDofCases[] = {
    {0, 0.6, 1.0}, {1, 1.4, 1.0}, {2, 4.0, 4.0}, {3, 1.2, 4.0}, {4, 6.0, 4.0}, {5, 0.9, 2.25},
    {0, 3.0, 1.0}, {5, 2.0, 1.0}, {4, 0.6, 1.0},
};

// Float rounds each of ~1000 RK4 steps at ~eps of the state; double's error
// is RK4 truncation, (omega_n dt)^4 ~ 1e-8 and below.
template <typename S>
double response_tol(double step) {
  return (std::is_same<S, float>::value ? 3e-5 : 1e-8) * std::abs(step);
}

TYPED_TEST(ReferenceModelTest, SingleDofStepFollowsTheAnalyticSecondOrderResponse) {
  using S = TypeParam;
  const double dt = 0.01;
  for (const DofCase& c : kDofCases) {
    const bool angle = c.dof >= 3;
    SecondOrder so{c.lambda, c.omega, angle ? 0.1 : 0.2, angle ? 0.6 : 1.2};
    Vector6<S> lambda_d = Vector6<S>::Constant(S(1.7)), omega = Vector6<S>::Constant(S(0.8));
    lambda_d(c.dof) = static_cast<S>(c.lambda);
    omega(c.dof) = static_cast<S>(c.omega);
    Vector6<S> eta0 = Vector6<S>::Zero(), r = Vector6<S>::Zero();
    eta0(c.dof) = static_cast<S>(so.x0);
    r(c.dof) = static_cast<S>(so.r);
    ReferenceModel<S> ref(lambda_d, omega, eta0);
    DesiredState<S> d;
    double err_x = 0, err_v = 0, err_a = 0, peak = so.x0, others = 0;
    for (int k = 1; k <= 1000; ++k) {
      ASSERT_EQ(ref.step(r, static_cast<S>(dt), d), Status::ok);
      double x, v, a;
      so.at(k * dt, x, v, a);
      err_x = std::max(err_x, std::abs(double(d.eta_d(c.dof)) - x));
      err_v = std::max(err_v, std::abs(double(d.eta_d_dot(c.dof)) - v));
      err_a = std::max(err_a, std::abs(double(d.eta_d_ddot(c.dof)) - a));
      peak = std::max(peak, double(d.eta_d(c.dof)));
      for (int i = 0; i < 6; ++i)
        if (i != c.dof)
          others = std::max({others, std::abs(double(d.eta_d(i))), std::abs(double(d.eta_d_dot(i))),
                             std::abs(double(d.eta_d_ddot(i)))});
    }
    const double step = so.r - so.x0;
    const double tol = response_tol<S>(step);
    EXPECT_LT(err_x, tol) << "dof " << c.dof << " zeta " << so.zeta();
    EXPECT_LT(err_v, tol * std::sqrt(c.omega) * 4) << "dof " << c.dof;
    EXPECT_LT(err_a, tol * c.omega * 8) << "dof " << c.dof;
    EXPECT_EQ(others, 0.0) << "a single-DOF command moved another DOF";
    // Overshoot of the sampled peak: the sample nearest the true peak is
    // within dt/2 of it, which costs at most |x''| dt^2 / 8 of the step.
    // Critically damped and overdamped responses never pass r.
    const double overshoot = (peak - so.r) / step;
    if (so.zeta() < 1)
      EXPECT_NEAR(overshoot, so.overshoot(), 2e-5 + 4 * tol / step)
          << "dof " << c.dof << " zeta = lambda_d / (2 sqrt(omega)) = " << so.zeta();
    else
      EXPECT_LE(overshoot, tol / step) << "dof " << c.dof << " zeta " << so.zeta();
  }
}

TYPED_TEST(ReferenceModelTest, GeneralCommandSettlesOnR) {
  using S = TypeParam;
  Vector6<S> lambda_d, omega, r, eta0;
  lambda_d << S(2), S(3), S(2.5), S(4), S(3.5), S(2);
  omega << S(1), S(2), S(1.5), S(4), S(3), S(1.2);
  r << S(1), S(-2), S(0.5), S(0.3), S(-0.2), S(1.0);
  eta0 << S(-0.5), S(0.4), S(0), S(-0.1), S(0.1), S(-0.5);
  ReferenceModel<S> ref(lambda_d, omega, eta0);
  DesiredState<S> d;
  const S dt = S(0.02);
  for (int k = 0; k < 3000; ++k) ASSERT_EQ(ref.step(r, dt, d), Status::ok);  // 60 s
  // After 60 s the slowest mode (~1/s near this attitude) has decayed far
  // below 1e-9. What is left is rounding, which in float is not small: once
  // dt * |nu_d| is under half an ulp of eta_d the pose stops moving while nu_d
  // still builds up, a dead band of |eta_d - r| ~ ulp(r) lambda_d / (omega dt)
  // (here ~1e-5; measured 4.4e-6). Double's floor at this dt is ~1e-13.
  const double ulp_r = static_cast<double>(eps<S>()) * 2.0;  // max |r| = 2
  const double tol = std::is_same<S, float>::value ? 4 * ulp_r * 2.0 / double(dt) : 1e-9;
  record("final_error", static_cast<double>((d.eta_d - r).cwiseAbs().maxCoeff()));
  EXPECT_LT((d.eta_d - r).cwiseAbs().maxCoeff(), S(tol));
  EXPECT_LT(ref.nu_d().cwiseAbs().maxCoeff(), S(tol));
  EXPECT_LT(d.eta_d_dot.cwiseAbs().maxCoeff(), S(tol));
  EXPECT_LT(d.eta_d_ddot.cwiseAbs().maxCoeff(), S(tol));
  EXPECT_TRUE((ref.eta_d().array() == d.eta_d.array()).all());
}

// eta_d_dot and eta_d_ddot are what every controller feeds on: with roll,
// pitch and yaw all moving they must be the time derivatives of the eta_d the
// model produces (central differences, O(dt^2)).
TEST(ReferenceModelDerivatives, DesiredVelocityAndAccelerationAreTheDerivativesOfEtaD) {
  Eigen::Matrix<double, 6, 1> lambda_d, omega, r;
  lambda_d << 1.5, 2, 2.5, 1.8, 2.2, 1.6;
  omega << 1, 1.5, 2, 2.5, 1.2, 0.9;
  r << 2, -1, 0.5, 0.4, -0.3, 1.2;
  ReferenceModel<double> ref(lambda_d, omega);
  const double dt = 1e-3;
  std::vector<DesiredState<double>> hist;
  DesiredState<double> d;
  for (int k = 0; k < 3000; ++k) {
    ASSERT_EQ(ref.step(r, dt, d), Status::ok);
    hist.push_back(d);
  }
  double err_v = 0, err_a = 0, size_a = 0;
  for (std::size_t k = 1; k + 1 < hist.size(); ++k) {
    const auto v_fd = (hist[k + 1].eta_d - hist[k - 1].eta_d) / (2 * dt);
    const auto a_fd = (hist[k + 1].eta_d_dot - hist[k - 1].eta_d_dot) / (2 * dt);
    err_v = std::max(err_v, (v_fd - hist[k].eta_d_dot).cwiseAbs().maxCoeff());
    err_a = std::max(err_a, (a_fd - hist[k].eta_d_ddot).cwiseAbs().maxCoeff());
    size_a = std::max(size_a, hist[k].eta_d_ddot.cwiseAbs().maxCoeff());
  }
  record("err_v", err_v);
  record("err_a", err_a);
  EXPECT_LT(err_v, 1e-5);
  EXPECT_LT(err_a, 1e-5);
  EXPECT_GT(size_a, 0.5);  // the check is not vacuous
}

// ------------------------------------------------------------------ bad input

template <typename S>
bool same_bits(const ReferenceModel<S>& a, const ReferenceModel<S>& b) {
  const auto eq = [](const Vector6<S>& x, const Vector6<S>& y) {
    return std::memcmp(x.data(), y.data(), sizeof(S) * 6) == 0;
  };
  return eq(a.eta_d(), b.eta_d()) && eq(a.nu_d(), b.nu_d()) &&
         eq(a.desired().eta_d, b.desired().eta_d) &&
         eq(a.desired().eta_d_dot, b.desired().eta_d_dot) &&
         eq(a.desired().eta_d_ddot, b.desired().eta_d_ddot);
}

template <typename S>
bool same_desired(const DesiredState<S>& a, const DesiredState<S>& b) {
  return (a.eta_d.array() == b.eta_d.array()).all() &&
         (a.eta_d_dot.array() == b.eta_d_dot.array()).all() &&
         (a.eta_d_ddot.array() == b.eta_d_ddot.array()).all();
}

TYPED_TEST(ReferenceModelTest, NonFiniteCommandOrBadDtIsRefusedAndTheStateIsUnchanged) {
  using S = TypeParam;
  Vector6<S> r;
  r << S(1), S(2), S(-1), S(0.2), S(0.1), S(0.5);
  ReferenceModel<S> ref(Vector6<S>::Constant(S(2)), Vector6<S>::Constant(S(1)));
  DesiredState<S> d;
  for (int k = 0; k < 5; ++k) ASSERT_EQ(ref.step(r, S(0.1), d), Status::ok);
  const ReferenceModel<S> before = ref;
  const S bad_values[3] = {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                           -std::numeric_limits<S>::infinity()};
  for (int i = 0; i < 6; ++i)
    for (const S bad : bad_values) {
      Vector6<S> rb = r;
      rb(i) = bad;
      DesiredState<S> out;
      out.eta_d.setConstant(S(9));
      EXPECT_EQ(ref.step(rb, S(0.1), out), Status::non_finite_input) << "r[" << i << "]";
      EXPECT_TRUE(same_bits(ref, before));
      EXPECT_TRUE(same_desired(out, before.desired())) << "out must keep the last good state";
    }
  for (const S dt : {S(0), S(-0.1), std::numeric_limits<S>::quiet_NaN(),
                     std::numeric_limits<S>::infinity()}) {
    DesiredState<S> out;
    EXPECT_EQ(ref.step(r, dt, out), Status::invalid_argument) << "dt = " << dt;
    EXPECT_TRUE(same_bits(ref, before));
    EXPECT_TRUE(same_desired(out, before.desired()));
  }
  // reset() refuses a non-finite pose and keeps the state.
  Vector6<S> nan_pose = r;
  nan_pose(2) = std::numeric_limits<S>::quiet_NaN();
  EXPECT_FALSE(ref.reset(nan_pose));
  EXPECT_TRUE(same_bits(ref, before));
}

TYPED_TEST(ReferenceModelTest, SingularPitchIsRefusedAndTheStateIsUnchanged) {
  using S = TypeParam;
  ReferenceModel<S> ref(Vector6<S>::Constant(S(2)), Vector6<S>::Constant(S(1)));
  Vector6<S> singular = Vector6<S>::Zero();
  singular(4) = static_cast<S>(kPi / 2);
  ASSERT_TRUE(ref.reset(singular));
  const ReferenceModel<S> before = ref;
  DesiredState<S> out;
  EXPECT_EQ(ref.step(Vector6<S>::Ones(), S(0.05), out), Status::near_singularity);
  EXPECT_TRUE(same_bits(ref, before));
}

// The pitch limit (reference_model.hpp): 90 deg - 0.2 rad for the command
// and for the reference; a step that limits is taken (ok) and says so.
TYPED_TEST(ReferenceModelTest, PitchIsLimitedShortOfTheSingularity) {
  using S = TypeParam;
  const S limit = ReferenceModel<S>::pitch_limit();
  EXPECT_EQ(limit, static_cast<S>(kPi / 2 - 0.2));
  for (const double command : {2.0, -2.0, 1e30, -1e30, kPi / 2 + 2 * kPi}) {
    SCOPED_TRACE(command);
    ReferenceModel<S> ref(Vector6<S>::Constant(S(2)), Vector6<S>::Constant(S(1)));
    Vector6<S> r = Vector6<S>::Zero();
    r(4) = static_cast<S>(command);
    DesiredState<S> d;
    for (int k = 0; k < 1000; ++k) {
      ASSERT_EQ(ref.step(r, S(0.05), d), Status::ok);
      ASSERT_TRUE(ref.pitch_limited());
      ASSERT_LE(std::abs(d.eta_d(4)), limit);
    }
    EXPECT_NEAR(d.eta_d(4), command > 0 ? limit : -limit, S(1e-4));
  }
  // Inside the limit nothing is limited: the analytic tests above hold there.
  ReferenceModel<S> ref(Vector6<S>::Constant(S(2)), Vector6<S>::Constant(S(1)));
  Vector6<S> r = Vector6<S>::Zero();
  r(4) = limit - S(0.01);
  DesiredState<S> d;
  for (int k = 0; k < 1000; ++k) {
    ASSERT_EQ(ref.step(r, S(0.05), d), Status::ok);
    ASSERT_FALSE(ref.pitch_limited()) << "step " << k;
  }
  // reset() clears the flag.
  r(4) = S(2);
  ASSERT_EQ(ref.step(r, S(0.05), d), Status::ok);
  ASSERT_TRUE(ref.pitch_limited());
  ASSERT_TRUE(ref.reset(Vector6<S>::Zero()));
  EXPECT_FALSE(ref.pitch_limited());
}

// A reference reset beyond 90 deg is held in the interval of width
// 2 pitch_limit() about 180 deg: commanded level, it goes to the near edge of
// that interval and stays on its side of the band. One reset between the
// limit and the band is put on the limit by its first step.
TYPED_TEST(ReferenceModelTest, ResetBeyondTheLimitIsHeldOnItsSideOfTheBand) {
  using S = TypeParam;
  const S limit = ReferenceModel<S>::pitch_limit();
  ReferenceModel<S> ref(Vector6<S>::Constant(S(2)), Vector6<S>::Constant(S(1)));
  Vector6<S> eta0 = Vector6<S>::Zero();
  eta0(4) = S(2);
  ASSERT_TRUE(ref.reset(eta0));
  DesiredState<S> d;
  for (int k = 0; k < 1000; ++k) {
    ASSERT_EQ(ref.step(Vector6<S>::Zero(), S(0.05), d), Status::ok);
    ASSERT_TRUE(ref.pitch_limited());
    ASSERT_GE(d.eta_d(4), static_cast<S>(kPi) - limit);
    ASSERT_TRUE(d.eta_d_dot.allFinite() && d.eta_d_ddot.allFinite());
  }
  EXPECT_NEAR(d.eta_d(4), static_cast<S>(kPi) - limit, S(1e-4));

  eta0(4) = S(1.5);  // between the limit (1.37) and the band
  ASSERT_TRUE(ref.reset(eta0));
  ASSERT_EQ(ref.step(Vector6<S>::Zero(), S(0.05), d), Status::ok);
  EXPECT_TRUE(ref.pitch_limited());
  EXPECT_LE(d.eta_d(4), limit);
  EXPECT_LE(d.eta_d_dot(4), S(0)) << "the pitch rate outwards is removed";
  for (int k = 0; k < 400; ++k) ASSERT_EQ(ref.step(Vector6<S>::Zero(), S(0.05), d), Status::ok);
  EXPECT_LT(std::abs(d.eta_d(4)), S(0.01));
}

TYPED_TEST(ReferenceModelTest, UnconfiguredModelRefusesToStep) {
  using S = TypeParam;
  ReferenceModel<S> ref;
  DesiredState<S> out;
  EXPECT_EQ(ref.step(Vector6<S>::Ones(), S(0.1), out), Status::invalid_argument);
}

TYPED_TEST(ReferenceModelTest, InvalidConfigurationNamesTheParameter) {
  using S = TypeParam;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  struct Case {
    const char* field;
    int which;  // 0 lambda_d, 1 omega, 2 eta0
    int index;
    S value;
  };
  const Case cases[] = {
      {"lambda_d", 0, 2, S(0)},  {"lambda_d", 0, 0, S(-1)}, {"lambda_d", 0, 5, nan},
      {"omega", 1, 3, S(0)},     {"omega", 1, 1, S(-0.5)},  {"omega", 1, 4, nan},
      {"eta0", 2, 0, nan},       {"eta0", 2, 4, static_cast<S>(kPi / 2)},
  };
  for (const Case& c : cases) {
    Vector6<S> v[3] = {Vector6<S>::Ones(), Vector6<S>::Ones(), Vector6<S>::Zero()};
    v[c.which](c.index) = c.value;
    ReferenceModel<S> out(Vector6<S>::Constant(S(3)), Vector6<S>::Constant(S(2)),
                          Vector6<S>::Constant(S(0.25)));
    const ReferenceModel<S> before = out;
    const ValidationError e = ReferenceModel<S>::create(v[0], v[1], v[2], out);
    EXPECT_STREQ(e.field, c.field);
    EXPECT_TRUE(same_bits(out, before)) << "create() wrote into `out` on failure";
    EXPECT_TRUE((out.lambda_d().array() == S(3)).all());
    try {
      ReferenceModel<S> thrown(v[0], v[1], v[2]);
      ADD_FAILURE() << "no exception for a bad " << c.field;
    } catch (const std::invalid_argument& ex) {
      EXPECT_NE(std::string(ex.what()).find(c.field), std::string::npos) << ex.what();
    }
  }
}

}  // namespace
