// The exhaustive hostile-input sweep (see test_reliability_controllers.cpp)
// of the models: reference model, vehicle dynamics and RK4, kinematics and
// the RBF network.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "neurov/neurov.hpp"
#include "controller_state.hpp"
#include "reliability_fixtures.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using namespace neurov_test;

NEUROV_SCALAR_SUITE(ReliabilityTest);

// ----------------------------------------------------------- reference model


template <typename S>
bool finite(const DesiredState<S>& d) {
  return d.eta_d.allFinite() && d.eta_d_dot.allFinite() && d.eta_d_ddot.allFinite();
}

TYPED_TEST(ReliabilityTest, ReferenceModelHostileCommandAndTimeStep) {
  using S = TypeParam;
  ReferenceModel<S> base(Vector6<S>::Constant(S(1)), Vector6<S>::Constant(S(0.25)));
  Vector6<S> r;
  r << S(10), S(-5), S(2), S(0.1), S(-0.2), S(1);
  DesiredState<S> d;
  for (int k = 0; k < 10; ++k) ASSERT_EQ(base.step(r, S(0.2), d), Status::ok);
  const Bytes before = state_of(base);
  auto check = [&](const Vector6<S>& cmd, S dt, const std::string& what) {
    ReferenceModel<S> m = base;
    DesiredState<S> out;
    out.eta_d.setConstant(S(7));
    const Status st = m.step(cmd, dt, out);
    EXPECT_TRUE(finite(out)) << what;
    EXPECT_TRUE(finite(m.desired())) << what;
    if (st != Status::ok) {
      EXPECT_TRUE(state_of(m) == before) << what << ": refused step changed the state";
      EXPECT_TRUE((out.eta_d.array() == base.desired().eta_d.array()).all())
          << what << ": a refused step must hand back the last good desired state";
    }
    return st;
  };
  for (int i = 0; i < 6; ++i)
    for (const S v : hostile_values<S>()) {
      Vector6<S> cmd = r;
      cmd(i) = v;
      const std::string what = "r[" + std::to_string(i) + "] = " + show(v);
      const Status st = check(cmd, S(0.2), what);
      if (!std::isfinite(v)) {
        EXPECT_EQ(st, Status::non_finite_input) << what;
      }
    }
  for (const S dt : hostile_values<S>()) {
    const Status st = check(r, dt, "dt = " + show(dt));
    if (!(std::isfinite(dt) && dt > S(0) && dt <= S(neurov::kMaxStep))) {
      EXPECT_EQ(st, Status::invalid_argument) << show(dt);
    }
  }
}

// Commanding a pitch of 90 deg leads the reference to the pitch limit,
// 90 deg - kPitchMargin, well short of the singular band: every step is taken
// (ok) with pitch_limited(), the pitch creeps up on the limit and never passes
// it, and a command back to level brings it back.
TYPED_TEST(ReliabilityTest, ReferenceModelCommandedIntoTheSingularityStopsShort) {
  using S = TypeParam;
  ReferenceModel<S> ref(Vector6<S>::Constant(S(2)), Vector6<S>::Constant(S(1)));
  const S limit = ReferenceModel<S>::pitch_limit();
  Vector6<S> up = Vector6<S>::Zero();
  up(4) = static_cast<S>(kPi / 2);
  DesiredState<S> d;
  for (int k = 0; k < 2000; ++k) {
    ASSERT_EQ(ref.step(up, S(0.05), d), Status::ok) << "step " << k;
    ASSERT_TRUE(ref.pitch_limited());
    ASSERT_TRUE(finite(d));
    ASSERT_LE(ref.eta_d()(4), limit);
  }
  EXPECT_NEAR(ref.eta_d()(4), limit, S(1e-4));
  EXPECT_GT(std::cos(ref.eta_d()(4)), S(0.19));  // |1/cos| <= 5.1
  for (int k = 0; k < 400; ++k) ASSERT_EQ(ref.step(Vector6<S>::Zero(), S(0.05), d), Status::ok);
  EXPECT_FALSE(ref.pitch_limited());
  EXPECT_LT(std::abs(ref.eta_d()(4)), S(0.1)) << "stuck at the singularity";
}

// A command beyond 90 deg used to carry the reference over the singular band
// in one step (7e-4 rad wide in float), where every step back with an RK4
// stage in the band was refused for ever. The pitch limit keeps it on this
// side, with every step taken, and it comes back when commanded level.
TYPED_TEST(ReliabilityTest, ReferenceModelComesBackAcrossTheSingularity) {
  using S = TypeParam;
  ReferenceModel<S> ref(Vector6<S>::Constant(S(2)), Vector6<S>::Constant(S(1)));
  Vector6<S> over = Vector6<S>::Zero();
  over(4) = S(2);
  DesiredState<S> d;
  for (int k = 0; k < 400; ++k) {
    ASSERT_EQ(ref.step(over, S(0.05), d), Status::ok) << "step " << k;
    ASSERT_TRUE(ref.pitch_limited());
    ASSERT_TRUE(finite(d));
    ASSERT_LE(ref.eta_d()(4), ReferenceModel<S>::pitch_limit());
  }
  for (int k = 0; k < 400; ++k) {
    ASSERT_EQ(ref.step(Vector6<S>::Zero(), S(0.05), d), Status::ok) << "step " << k;
    ASSERT_TRUE(finite(d));
  }
  EXPECT_LT(std::abs(ref.eta_d()(4)), S(0.1)) << "stuck beyond the singularity";
}

// What the clamped command does not catch: an underdamped pitch overshoots a
// command inside the limit. Without the wall it went over 90 deg (across the
// band, or refused for a while in float where a stage landed in it). Now it is
// held at the limit, every step is taken and finite, and it comes back; with
// roll and yaw moving too, at the paper's 5 Hz, where J^T Omega J is stiff
// near 90 deg.
TYPED_TEST(ReliabilityTest, ReferenceModelOvershootIsHeldAtThePitchLimit) {
  using S = TypeParam;
  const S limit = ReferenceModel<S>::pitch_limit();
  for (const bool six_dof : {false, true}) {
    SCOPED_TRACE(six_dof ? "6 DOF" : "pitch alone");
    Vector6<S> lambda_d = Vector6<S>::Constant(S(1)), omega = Vector6<S>::Constant(S(1));
    lambda_d(4) = S(0.2);  // zeta = 0.1: 73 % overshoot
    Vector6<S> eta0 = Vector6<S>::Zero(), r = Vector6<S>::Zero();
    eta0(4) = -limit;
    r(4) = limit - S(0.01);
    if (six_dof) r << 1, 2, 3, S(0.5), limit - S(0.01), S(-1);
    ReferenceModel<S> ref(lambda_d, omega, eta0);
    DesiredState<S> d;
    int held = 0;
    for (int k = 0; k < 500; ++k) {
      ASSERT_EQ(ref.step(r, S(0.2), d), Status::ok) << "step " << k;
      ASSERT_TRUE(finite(d));
      ASSERT_LE(std::abs(ref.eta_d()(4)), limit) << "step " << k;
      held += ref.pitch_limited();
    }
    EXPECT_GT(held, 0) << "the overshoot never reached the limit";
    for (int k = 0; k < 1000; ++k) ASSERT_EQ(ref.step(Vector6<S>::Zero(), S(0.2), d), Status::ok);
    EXPECT_LT(ref.eta_d().cwiseAbs().maxCoeff(), S(1e-3));
  }
}

// ------------------------------------------------------------ vehicle, RK4

TYPED_TEST(ReliabilityTest, DynamicsAndRk4HostileValueInEveryEntry) {
  using S = TypeParam;
  const Vehicle<S> vehicle(nerov_parameters<S>());
  Rng rng(40);
  const Vector6<S> eta = rng.pose<S>(1.0), nu = rng.velocity<S>();
  const Vector6<S> tau = rng.vec6<S>(-200, 200);
  const Vector3<S> current = rng.vec3<S>(-0.5, 0.5);
  // Arguments 0..3: eta, nu, tau, current.
  auto run = [&](int a, int i, S v) {
    Vector6<S> e = eta, n = nu, t = tau;
    Vector3<S> c = current;
    if (a == 0) e(i) = v;
    if (a == 1) n(i) = v;
    if (a == 2) t(i) = v;
    if (a == 3) c(i) = v;
    static const char* const names[4] = {"eta", "nu", "tau", "current"};
    const std::string what = std::string(names[a]) + "[" + std::to_string(i) + "] = " + show(v);
    Vector6<S> eta_dot, nu_dot;
    const Status sd = vehicle.derivative(e, n, t, c, eta_dot, nu_dot);
    EXPECT_TRUE(eta_dot.allFinite() && nu_dot.allFinite()) << "derivative, " << what;
    if (!std::isfinite(v)) {
      EXPECT_EQ(sd, Status::non_finite_input) << what;
    }
    const Status sa = vehicle.acceleration(e, n, t, c, nu_dot);
    EXPECT_TRUE(nu_dot.allFinite()) << "acceleration, " << what;
    if (!std::isfinite(v)) {
      EXPECT_EQ(sa, Status::non_finite_input) << what;
    }
    const Vector6<S> e0 = e, n0 = n;
    const Status sr = rk4_step(vehicle, e, n, t, S(0.02), c);
    // A refused step hands the (possibly non-finite) state back unchanged.
    if (e0.allFinite() && n0.allFinite()) {
      EXPECT_TRUE(e.allFinite() && n.allFinite()) << "rk4_step, " << what;
    }
    if (sr != Status::ok && sr != Status::near_singularity) {
      EXPECT_EQ(std::memcmp(e.data(), e0.data(), sizeof(S) * 6), 0) << what;
      EXPECT_EQ(std::memcmp(n.data(), n0.data(), sizeof(S) * 6), 0) << what;
    }
    if (!std::isfinite(v)) {
      EXPECT_EQ(sr, Status::non_finite_input) << what;
    }
  };
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < (a == 3 ? 3 : 6); ++i)
      for (const S v : hostile_values<S>()) run(a, i, v);
  // dt: non-positive, non-finite or above kMaxStep is refused with the state untouched.
  for (const S dt : hostile_values<S>()) {
    Vector6<S> e = eta, n = nu;
    const Status st = rk4_step(vehicle, e, n, tau, dt, current);
    EXPECT_TRUE(e.allFinite() && n.allFinite()) << "dt = " << show(dt);
    if (!(std::isfinite(dt) && dt > S(0) && dt <= S(neurov::kMaxStep))) {
      EXPECT_EQ(st, Status::invalid_argument) << show(dt);
      EXPECT_TRUE((e.array() == eta.array()).all() && (n.array() == nu.array()).all());
    }
  }
  // An empty vehicle refuses everything.
  Vector6<S> e = eta, n = nu, nu_dot;
  EXPECT_EQ(rk4_step(Vehicle<S>{}, e, n, tau, S(0.1)), Status::invalid_argument);
  EXPECT_EQ(Vehicle<S>{}.acceleration(eta, nu, tau, nu_dot), Status::invalid_argument);
  EXPECT_TRUE(nu_dot.allFinite());
}

// --------------------------------------------------------------- kinematics

TYPED_TEST(ReliabilityTest, KinematicsOutputsStayFiniteForHostileValues) {
  using S = TypeParam;
  Rng rng(41);
  const Vector6<S> eta = rng.pose<S>(1.0), nu = rng.velocity<S>();
  Matrix6<S> m;
  for (int i = 0; i < 6; ++i)
    for (const S v : hostile_values<S>()) {
      const std::string what = "[" + std::to_string(i) + "] = " + show(v);
      Vector6<S> e = eta;
      e(i) = v;
      const Status sj = jacobian(e, m);
      EXPECT_TRUE(m.allFinite()) << "jacobian, eta" << what;
      const Status si = jacobian_inverse(e, m);
      EXPECT_TRUE(m.allFinite()) << "jacobian_inverse, eta" << what;
      if (!std::isfinite(v) && i >= 3) {
        EXPECT_EQ(sj, Status::non_finite_input) << what;
        EXPECT_EQ(si, Status::non_finite_input) << what;
      }
      (void)jacobian_dot(e, nu, m);
      EXPECT_TRUE(m.allFinite()) << "jacobian_dot, eta" << what;
      Vector6<S> n = nu;
      n(i) = v;
      if (!std::isfinite(v)) {
        EXPECT_EQ(jacobian_dot(eta, n, m), Status::non_finite_input) << what;
        EXPECT_TRUE(m.allFinite()) << "jacobian_dot, nu" << what;
      }
    }
}

// A finite angular rate so large that J_dot overflows must come back as
// non_finite_output and a finite matrix, like every other function here.
TYPED_TEST(ReliabilityTest, JacobianDotOfAHugeRateReportsTheOverflow) {
  using S = TypeParam;
  Rng rng(43);
  const Vector6<S> eta = rng.pose<S>(1.0);
  Matrix6<S> m;
  for (int i = 3; i < 6; ++i)
    for (const S v : {std::numeric_limits<S>::max(), std::numeric_limits<S>::lowest()}) {
      Vector6<S> nu = rng.velocity<S>();
      nu(i) = v;
      const Status st = jacobian_dot(eta, nu, m);
      EXPECT_TRUE(m.allFinite()) << "nu[" << i << "] = " << show(v) << ": " << to_string(st);
      if (!m.allFinite() || st != Status::ok) {
        EXPECT_EQ(st, Status::non_finite_output);
      }
    }
}

// ---------------------------------------------------------------- RBF network

TYPED_TEST(ReliabilityTest, RbfBasisIsFiniteAndInTheUnitIntervalForHostileInput) {
  using S = TypeParam;
  using Net = RbfNetwork<S>;
  Rng rng(42);
  const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> centres =
      rng.matrix(5, 4, -1, 1).template cast<S>();
  Net net;
  ASSERT_TRUE(Net::create(centres, Eigen::Matrix<S, Eigen::Dynamic, 1>::Constant(5, S(0.7)), net).ok());
  Eigen::Matrix<S, Eigen::Dynamic, 1> g(5);
  Eigen::Matrix<S, 6, 1> y;
  for (int i = 0; i < 4; ++i)
    for (const S v : hostile_values<S>()) {
      Eigen::Matrix<S, Eigen::Dynamic, 1> x = Eigen::Matrix<S, Eigen::Dynamic, 1>::Zero(4);
      x(i) = v;
      const Status st = net.output(x, g, y);
      EXPECT_TRUE(g.allFinite() && y.allFinite()) << show(v);
      EXPECT_TRUE((g.array() >= S(0)).all() && (g.array() <= S(1)).all()) << show(v);
      if (!std::isfinite(v)) {
        EXPECT_EQ(st, Status::non_finite_input);
      }
    }
  // Wrong sizes: refused, g zeroed, nothing read out of bounds.
  Eigen::Matrix<S, Eigen::Dynamic, 1> x3 = Eigen::Matrix<S, Eigen::Dynamic, 1>::Zero(3), g4(4);
  EXPECT_EQ(net.basis(x3, g), Status::invalid_argument);
  EXPECT_EQ(net.basis(Eigen::Matrix<S, Eigen::Dynamic, 1>::Zero(4), g4), Status::invalid_argument);
  EXPECT_TRUE(g4.allFinite());
  EXPECT_EQ(Net{}.basis(x3, g), Status::invalid_argument);
}

TYPED_TEST(ReliabilityTest, RbfNetworkCreateNamesTheBadField) {
  using S = TypeParam;
  using Net = RbfNetwork<S>;
  using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  const Mat c = Mat::Ones(3, 2);
  const Vec w = Vec::Ones(3), off = Vec::Zero(2), sc = Vec::Ones(2);
  struct Case {
    const char* what;
    Mat centres;
    Vec widths, offset, scale;
    const char* field;
  };
  auto with = [](Vec v, int i, S x) {
    v(i) = x;
    return v;
  };
  Mat c_nan = c;
  c_nan(2, 1) = nan;
  const Case cases[] = {
      {"empty centre set", Mat(0, 2), Vec(0), off, sc, "centres"},
      {"centres with no inputs", Mat(3, 0), w, Vec(0), Vec(0), "centres"},
      {"fewer widths than centres", c, Vec::Ones(2), off, sc, "widths"},
      {"more widths than centres", c, Vec::Ones(4), off, sc, "widths"},
      {"offset of the wrong size", c, w, Vec::Zero(3), sc, "input_offset"},
      {"scale of the wrong size", c, w, off, Vec::Ones(1), "input_scale"},
      {"NaN centre", c_nan, w, off, sc, "centres"},
      {"zero width", c, with(w, 1, S(0)), off, sc, "widths"},
      {"negative width", c, with(w, 0, S(-1)), off, sc, "widths"},
      {"NaN width", c, with(w, 2, nan), off, sc, "widths"},
      {"infinite width", c, with(w, 2, inf), off, sc, "widths"},
      {"width whose 1/(2 sigma^2) overflows", c, with(w, 0, std::numeric_limits<S>::denorm_min()),
       off, sc, "widths (1 / (2 sigma^2) overflows)"},
      {"NaN offset", c, w, with(off, 0, nan), sc, "input_offset"},
      {"zero scale", c, w, off, with(sc, 1, S(0)), "input_scale"},
      {"negative scale", c, w, off, with(sc, 1, S(-2)), "input_scale"},
  };
  for (const Case& k : cases) {
    Net out;
    const ValidationError e = Net::create(k.centres, k.widths, k.offset, k.scale, out);
    ASSERT_FALSE(e.ok()) << k.what;
    EXPECT_STREQ(e.field, k.field) << k.what;
    EXPECT_FALSE(out.configured()) << k.what << ": create() wrote into `out`";
    char buf[256];
    e.format(buf, sizeof buf);
    EXPECT_NE(std::string(buf).find(k.field), std::string::npos) << buf;
  }
  // The NN controller passes the network's own error through.
  using Ctl = NNAdaptiveController<S>;
  Ctl ctl;
  typename Ctl::Network::CentreMatrix none(0, kNNInputs);
  const ValidationError e =
      Ctl::create(none, typename Ctl::BasisVector(0), Ctl::InputVector::Zero(),
                  Ctl::InputVector::Ones(), NNAdaptiveConfig<S>{}, ctl);
  EXPECT_STREQ(e.field, "centres");
  EXPECT_FALSE(ctl.configured());
}

}  // namespace
