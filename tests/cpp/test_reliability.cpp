// Reliability under hostile input: every public entry point of the real-time
// path is swept with NaN, +-Inf, the largest finite numbers, huge but
// plausible "glitch" values, denormals and -0 in every entry of every input,
// and with poses at and around the pitch singularity. The rules checked are
// the library's promises (status.hpp, the controller headers):
//  * every output is finite, whatever the input;
//  * a step that returns anything but `ok` writes tau = 0 and leaves the
//    object's state bit-for-bit as it was (weights, theta_hat, integrator,
//    reference-model state, plant state);
//  * an `ok` step leaves finite state behind;
//  * so a controller fed a mix of good and bad calls ends exactly where a twin
//    fed only the good ones does: a refused call loses nothing.
// The per-function tests (test_controllers.cpp, ...) check NaN/Inf at a few
// entries; this file is the exhaustive sweep that docs/reliability.md cites.
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
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::kPi;
using neurov_test::Rng;

template <typename S>
class ReliabilityTest : public ::testing::Test {};
TYPED_TEST_SUITE(ReliabilityTest, neurov_test::Scalars, neurov_test::ScalarName);

/// Values no sane sensor or caller produces but a broken one can.
template <typename S>
std::vector<S> hostile_values() {
  using L = std::numeric_limits<S>;
  return {L::quiet_NaN(),       -L::quiet_NaN(),     L::infinity(),
          -L::infinity(),       L::max(),            L::lowest(),
          std::sqrt(L::max()),  -std::sqrt(L::max()), static_cast<S>(1e15),
          static_cast<S>(-1e9), L::denorm_min(),     static_cast<S>(-0.0)};
}

template <typename S>
std::string show(S v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(v));
  return buf;
}

// ----------------------------------------------------------- state snapshots

/// Raw bytes of every piece of state a controller exposes, so "unchanged"
/// means bit-for-bit (NaN == NaN, -0 != +0).
class Bytes {
 public:
  template <typename Derived>
  Bytes& add(const Eigen::MatrixBase<Derived>& m) {
    const auto e = m.eval();
    const auto* p = reinterpret_cast<const unsigned char*>(e.data());
    b_.insert(b_.end(), p, p + sizeof(typename Derived::Scalar) * static_cast<size_t>(e.size()));
    return *this;
  }
  template <typename T>
  Bytes& value(const T& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    b_.insert(b_.end(), p, p + sizeof v);
    return *this;
  }
  bool operator==(const Bytes& o) const { return b_ == o.b_; }

 private:
  std::vector<unsigned char> b_;
};

template <typename S>
Bytes& add_tracking(Bytes& b, const TrackingError<S>& e) {
  return b.add(e.eta_tilde).add(e.eta_tilde_dot).add(e.s).add(e.eta_r_dot).add(e.eta_r_ddot)
      .add(e.nu_r).add(e.nu_r_dot).add(e.kinematics.R).add(e.kinematics.T);
}

template <typename S, int N>
Bytes state_of(const NNAdaptiveController<S, N>& c) {
  Bytes b;
  b.add(c.weights()).value(c.weight_norm()).add(c.network_output()).add(c.learning_rates())
      .add(c.basis()).value(c.adapted());
  return add_tracking(b, c.tracking());
}
template <typename S>
Bytes state_of(const LinearAdaptiveController<S>& c) {
  Bytes b;
  b.add(c.theta()).add(c.model_output());
  return add_tracking(b, c.tracking());
}
template <typename S>
Bytes state_of(const PDController<S>& c) {
  Bytes b;
  return add_tracking(b, c.tracking());
}
template <typename S>
Bytes state_of(const PIDController<S>& c) {
  Bytes b;
  b.add(c.integral());
  return add_tracking(b, c.tracking());
}
template <typename S>
Bytes state_of(const SlidingModeController<S>& c) {
  Bytes b;
  b.add(c.model_output());
  return add_tracking(b, c.tracking());
}
template <typename S>
Bytes state_of(const ComputedTorqueController<S>& c) {
  Bytes b;
  b.add(c.model_output());
  return add_tracking(b, c.tracking());
}

template <typename S, int N>
bool state_finite(const NNAdaptiveController<S, N>& c) {
  return c.weights().allFinite() && std::isfinite(c.weight_norm()) && c.tracking().s.allFinite();
}
template <typename S>
bool state_finite(const LinearAdaptiveController<S>& c) {
  return c.theta().allFinite() && c.tracking().s.allFinite();
}
template <typename S>
bool state_finite(const PDController<S>& c) {
  return c.tracking().s.allFinite();
}
template <typename S>
bool state_finite(const PIDController<S>& c) {
  return c.integral().allFinite() && c.tracking().s.allFinite();
}
template <typename S>
bool state_finite(const SlidingModeController<S>& c) {
  return c.model_output().allFinite() && c.tracking().s.allFinite();
}
template <typename S>
bool state_finite(const ComputedTorqueController<S>& c) {
  return c.model_output().allFinite() && c.tracking().s.allFinite();
}

// ------------------------------------------------------------- controllers

/// Step arguments of a regular situation: moderate pitch, errors of a few
/// tenths, so the good steps are `ok` and the weights move.
template <typename S>
struct StepArgs {
  Vector6<S> v[5];
};

template <typename S>
StepArgs<S> good_args(Rng& rng) {
  StepArgs<S> a;
  a.v[0] = rng.pose<S>(1.0);
  a.v[1] = rng.velocity<S>();
  a.v[2] = a.v[0] + rng.vec6<S>(-0.3, 0.3);
  a.v[3] = rng.vec6<S>(-0.5, 0.5);
  a.v[4] = rng.vec6<S>(-0.5, 0.5);
  return a;
}

template <typename Ctl, typename S>
Status step(Ctl& c, const StepArgs<S>& a, Vector6<S>& tau) {
  return c.step(a.v[0], a.v[1], a.v[2], a.v[3], a.v[4], tau);
}

const char* const kArg[5] = {"eta", "nu", "eta_d", "eta_d_dot", "eta_d_ddot"};

/// One call on a copy of `base`: tau finite; a refusal zeroes tau and keeps
/// the state; an accepted step leaves finite state. Returns the status.
template <typename Ctl, typename S>
Status check_one_step(const Ctl& base, const StepArgs<S>& in, const std::string& what) {
  Ctl c = base;
  const Bytes before = state_of(c);
  Vector6<S> tau = Vector6<S>::Constant(S(7));
  const Status st = step(c, in, tau);
  EXPECT_TRUE(tau.allFinite()) << what << ": tau = " << tau.transpose();
  EXPECT_EQ(c.last_status(), st) << what;
  if (st != Status::ok) {
    EXPECT_TRUE((tau.array() == S(0)).all()) << what << ": refused with tau = " << tau.transpose();
    EXPECT_TRUE(state_of(c) == before) << what << ": refused step changed the state";
  } else {
    EXPECT_TRUE(state_finite(c)) << what << ": accepted step left non-finite state";
  }
  return st;
}

/// Every entry of every argument, every hostile value.
template <typename Ctl>
void sweep_controller(Ctl base, std::uint32_t seed) {
  using S = typename Ctl::Scalar;
  Rng rng(seed);
  const StepArgs<S> good = good_args<S>(rng);
  Vector6<S> tau;
  for (int k = 0; k < 3; ++k)  // a history, so "unchanged" means something
    ASSERT_EQ(step(base, good_args<S>(rng), tau), Status::ok);
  int refused = 0, accepted = 0;
  for (int a = 0; a < 5; ++a)
    for (int i = 0; i < 6; ++i)
      for (const S v : hostile_values<S>()) {
        StepArgs<S> in = good;
        in.v[a](i) = v;
        const std::string what = std::string(kArg[a]) + "[" + std::to_string(i) + "] = " + show(v);
        const Status st = check_one_step(base, in, what);
        (st == Status::ok ? accepted : refused)++;
        if (!std::isfinite(v)) {
          EXPECT_EQ(st, Status::non_finite_input) << what;
        }
      }
  // Every controller refuses the 180 non-finite cases; huge finite ones may go
  // either way, but some of each must occur or the sweep tests nothing.
  EXPECT_GE(refused, 5 * 6 * 4);
  EXPECT_GT(accepted, 0);
  // The whole state vector at once: all NaN, all huge.
  for (const S v : {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::max()}) {
    StepArgs<S> in;
    for (auto& x : in.v) x.setConstant(v);
    check_one_step(base, in, "every input = " + show(v));
  }
}

/// Pitch at, just inside and just outside the singularity threshold, and a
/// full turn away: inside is refused (near_singularity) with tau = 0 and the
/// state kept; outside is accepted with a finite tau. eta_d's pitch does not
/// enter J, so a singular eta_d is accepted.
template <typename Ctl>
void singularity_band(const Ctl& base, std::uint32_t seed) {
  using S = typename Ctl::Scalar;
  Rng rng(seed);
  StepArgs<S> good = good_args<S>(rng);
  const double thr = static_cast<double>(singularity_threshold<S>());
  for (const double sign : {1.0, -1.0}) {
    const double half_pi = sign * kPi / 2;
    // acos-based offsets give |cos(theta)| at the stated multiple of the threshold.
    struct Case {
      double pitch;
      bool singular;
      const char* what;
    };
    const Case cases[] = {
        {half_pi, true, "at +-pi/2"},
        {half_pi + 2 * sign * kPi, true, "+-pi/2 plus a turn"},
        {sign * std::acos(0.25 * thr), true, "|cos| = threshold / 4"},
        {sign * std::acos(0.5 * thr), true, "|cos| = threshold / 2"},
        {sign * (kPi - std::acos(0.5 * thr)), true, "beyond, |cos| = threshold / 2"},
        {sign * std::acos(4.0 * thr), false, "|cos| = 4 threshold"},
        {sign * std::acos(100.0 * thr), false, "|cos| = 100 threshold"},
        {sign * 1.5, false, "1.5 rad"},
    };
    for (const Case& c : cases) {
      StepArgs<S> in = good;
      in.v[0](4) = static_cast<S>(c.pitch);
      const bool singular = std::abs(std::cos(in.v[0](4))) < singularity_threshold<S>();
      ASSERT_EQ(singular, c.singular) << c.what << " (test set-up)";
      const std::string what = std::string("pitch ") + c.what + " = " + show(in.v[0](4));
      const Status st = check_one_step(base, in, what);
      if (c.singular) {
        EXPECT_EQ(st, Status::near_singularity) << what;
      } else {
        // Close to the singularity, 1/cos(theta) is large and a huge tau may
        // overflow in float; either way the rules above held.
        EXPECT_TRUE(st == Status::ok || st == Status::non_finite_output) << what << ": "
                                                                         << to_string(st);
      }
      StepArgs<S> desired_singular = good;
      desired_singular.v[2](4) = static_cast<S>(c.pitch);
      EXPECT_EQ(check_one_step(base, desired_singular, std::string("eta_d ") + what), Status::ok);
    }
  }
}

/// A random mix of good and bad calls against a twin that sees only the good
/// ones: identical taus on the good calls and identical state at the end.
template <typename Ctl>
void nothing_lost(Ctl ctl, std::uint32_t seed) {
  using S = typename Ctl::Scalar;
  Rng rng(seed);
  Ctl twin = ctl;
  const std::vector<S> bad = hostile_values<S>();
  std::uniform_int_distribution<int> pick_arg(0, 4), pick_entry(0, 5),
      pick_value(0, static_cast<int>(bad.size()) - 1), coin(0, 2);
  int good_calls = 0, refused = 0;
  for (int k = 0; k < 300; ++k) {
    StepArgs<S> in = good_args<S>(rng);
    if (coin(rng.engine()) == 0) {
      StepArgs<S> b = in;
      b.v[pick_arg(rng.engine())](pick_entry(rng.engine())) = bad[pick_value(rng.engine())];
      Ctl probe = ctl;
      Vector6<S> tau;
      if (step(probe, b, tau) != Status::ok) {
        // Refused on the real controller too, and nothing of it may remain.
        ASSERT_NE(step(ctl, b, tau), Status::ok);
        ASSERT_TRUE(tau.allFinite());
        ++refused;
      }
    }
    Vector6<S> tau, tau_twin;
    const Status s1 = step(ctl, in, tau), s2 = step(twin, in, tau_twin);
    ASSERT_EQ(s1, s2);
    ASSERT_EQ(std::memcmp(tau.data(), tau_twin.data(), sizeof(S) * 6), 0) << "call " << k;
    ++good_calls;
  }
  EXPECT_GT(refused, 25);  // of ~100 bad calls; huge finite values are often accepted
  EXPECT_TRUE(state_of(ctl) == state_of(twin));
}

template <typename S, int N = Eigen::Dynamic>
NNAdaptiveController<S, N> nn(RobustModification mod, std::uint32_t seed, S dead_zone = S(0)) {
  using Ctl = NNAdaptiveController<S, N>;
  Rng rng(seed);
  const int n = N == Eigen::Dynamic ? 16 : N;
  typename Ctl::Network::CentreMatrix centres(n, kNNInputs);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < kNNInputs; ++i) centres(j, i) = rng.uniform<S>(-1.5, 1.5);
  typename Ctl::Network net;
  EXPECT_TRUE(Ctl::Network::create(centres, Ctl::BasisVector::Constant(n, S(2)), net).ok());
  typename Ctl::WeightMatrix w(6, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < 6; ++i) w(i, j) = rng.uniform<S>(-20, 20);
  EXPECT_TRUE(net.set_weights(w));
  NNAdaptiveConfig<S> cfg;
  cfg.lambda.setConstant(S(0.8));
  cfg.kd << S(200), S(200), S(200), S(50), S(50), S(50);
  cfg.gamma = S(2);
  cfg.dt = S(0.2);
  cfg.modification = mod;
  cfg.sigma_m = S(0.1);
  cfg.kappa = S(0.05);
  cfg.w_max = S(100);
  cfg.dead_zone = dead_zone;
  Ctl c;
  EXPECT_TRUE(Ctl::create(net, cfg, c).ok());
  return c;
}

template <typename S>
LinearAdaptiveController<S> linear() {
  LinearAdaptiveConfig<S> cfg;
  cfg.kd << S(200), S(200), S(200), S(50), S(50), S(50);
  ParameterVector<S> theta;
  EXPECT_TRUE(regressor_parameters(nerov_parameters<S>(), theta).ok());
  cfg.theta0 = S(0.8) * theta;
  return LinearAdaptiveController<S>(cfg);
}

template <typename S>
PDController<S> pd() {
  PDConfig<S> cfg;
  cfg.kp.setConstant(S(100));
  cfg.kd.setConstant(S(200));
  return PDController<S>(cfg);
}

template <typename S>
PIDController<S> pid() {
  PIDConfig<S> cfg;
  cfg.kp.setConstant(S(100));
  cfg.ki.setConstant(S(10));
  cfg.kd.setConstant(S(200));
  return PIDController<S>(cfg);
}

template <typename S>
SlidingModeController<S> smc() {
  SlidingModeConfig<S> cfg;
  cfg.kd.setConstant(S(100));
  cfg.k.setConstant(S(20));
  cfg.phi.setConstant(S(0.1));
  EXPECT_TRUE(regressor_parameters(nerov_parameters<S>(), cfg.theta).ok());
  return SlidingModeController<S>(cfg);
}

template <typename S>
ComputedTorqueController<S> computed_torque() {
  ComputedTorqueConfig<S> cfg;
  cfg.kd << S(200), S(200), S(200), S(50), S(50), S(50);
  cfg.vehicle = nerov_parameters<S>();
  return ComputedTorqueController<S>(cfg);
}

/// Runs `check` on every controller and configuration a vehicle can fly.
template <typename S, typename F>
void for_each_controller(F&& check) {
  {
    SCOPED_TRACE("NN, no modification");
    check(nn<S>(RobustModification::none, 1), 11u);
  }
  {
    SCOPED_TRACE("NN, sigma");
    check(nn<S>(RobustModification::sigma, 2), 12u);
  }
  {
    SCOPED_TRACE("NN, e-modification");
    check(nn<S>(RobustModification::e_modification, 3), 13u);
  }
  {
    SCOPED_TRACE("NN, projection");
    check(nn<S>(RobustModification::projection, 4), 14u);
  }
  {
    SCOPED_TRACE("NN, dead zone");
    check(nn<S>(RobustModification::sigma, 5, S(0.05)), 15u);
  }
  {
    SCOPED_TRACE("NN, 8 centres fixed at compile time");
    check(nn<S, 8>(RobustModification::none, 6), 16u);
  }
  {
    SCOPED_TRACE("linear adaptive");
    check(linear<S>(), 17u);
  }
  {
    SCOPED_TRACE("PD");
    check(pd<S>(), 18u);
  }
  {
    SCOPED_TRACE("PID");
    check(pid<S>(), 19u);
  }
  {
    SCOPED_TRACE("sliding mode");
    check(smc<S>(), 20u);
  }
  {
    SCOPED_TRACE("computed torque");
    check(computed_torque<S>(), 21u);
  }
}

TYPED_TEST(ReliabilityTest, ControllerStepHostileValueInEveryEntry) {
  for_each_controller<TypeParam>([](auto c, std::uint32_t seed) { sweep_controller(c, seed); });
}

TYPED_TEST(ReliabilityTest, ControllerStepAtAndAroundThePitchSingularity) {
  for_each_controller<TypeParam>([](auto c, std::uint32_t seed) { singularity_band(c, seed); });
}

TYPED_TEST(ReliabilityTest, ControllerRefusedCallsLoseNothing) {
  for_each_controller<TypeParam>([](auto c, std::uint32_t seed) { nothing_lost(c, seed); });
}

TYPED_TEST(ReliabilityTest, UnconfiguredControllersRefuseEveryStep) {
  using S = TypeParam;
  const StepArgs<S> in = [] {
    Rng rng(3);
    return good_args<S>(rng);
  }();
  check_one_step(NNAdaptiveController<S>{}, in, "NN");
  check_one_step(NNAdaptiveController<S, 4>{}, in, "NN<4>");
  check_one_step(LinearAdaptiveController<S>{}, in, "linear");
  check_one_step(PDController<S>{}, in, "PD");
  check_one_step(PIDController<S>{}, in, "PID");
  check_one_step(SlidingModeController<S>{}, in, "SMC");
  check_one_step(ComputedTorqueController<S>{}, in, "computed torque");
  NNAdaptiveController<S> c;
  Vector6<S> tau;
  EXPECT_EQ(step(c, in, tau), Status::invalid_argument);
}

// basis() is g(x) of the last accepted step, like tracking() and
// network_output(); a step refused after the network has run (an overflowing
// K_d s or update) must not leave the refused input's g behind. (state_of()
// includes basis() too, so every refusal test above checks it as well.)
TYPED_TEST(ReliabilityTest, NNRefusedStepKeepsTheBasisOfTheLastAcceptedStep) {
  using S = TypeParam;
  auto check = [](auto base, std::uint32_t seed) {
    Rng rng(seed);
    const StepArgs<S> good = good_args<S>(rng);
    Vector6<S> tau;
    ASSERT_EQ(step(base, good, tau), Status::ok);
    int late_refusals = 0;
    for (int a = 0; a < 5; ++a)
      for (int i = 0; i < 6; ++i)
        for (const S v : hostile_values<S>()) {
          StepArgs<S> in = good;
          in.v[a](i) = v;
          auto c = base;
          if (step(c, in, tau) != Status::non_finite_output) continue;
          ++late_refusals;
          EXPECT_TRUE(Bytes().add(c.basis()) == Bytes().add(base.basis()))
              << kArg[a] << "[" << i << "] = " << show(v);
        }
    EXPECT_GT(late_refusals, 0);
  };
  check(nn<S>(RobustModification::none, 1), 11u);
  check(nn<S>(RobustModification::sigma, 2), 12u);
  check(nn<S, 8>(RobustModification::none, 6), 16u);
}

// Finite weights whose Frobenius norm overflows (entries near the largest
// number) would leave weight_norm() inf, and every adapting step after refused
// (its overflow bound starts from the norm); the fuzzer found them accepted.
TYPED_TEST(ReliabilityTest, NNSetWeightsRefusesWeightsWhoseNormOverflows) {
  using S = TypeParam;
  auto c = nn<S>(RobustModification::none, 8);
  auto w = c.weights();
  w.setConstant(std::numeric_limits<S>::max() / S(2));
  const Bytes before = state_of(c);
  EXPECT_FALSE(c.set_weights(w));
  EXPECT_TRUE(std::isfinite(c.weight_norm()));
  EXPECT_TRUE(state_of(c) == before);
}

// A bad weight matrix or learning rate is refused and leaves the old ones.
TYPED_TEST(ReliabilityTest, NNSettersRefuseNonFiniteAndWrongSizes) {
  using S = TypeParam;
  auto c = nn<S>(RobustModification::none, 7);
  const Bytes before = state_of(c);
  for (const S v : hostile_values<S>()) {
    if (std::isfinite(v)) continue;
    auto w = c.weights();
    w(3, 2) = v;
    EXPECT_FALSE(c.set_weights(w));
    auto rates = c.learning_rates();
    rates(1) = v;
    EXPECT_FALSE(c.set_learning_rates(rates));
  }
  EXPECT_FALSE(c.set_weights(Eigen::Matrix<S, 6, Eigen::Dynamic>::Zero(6, 3)));
  EXPECT_FALSE(c.set_learning_rates(Eigen::Matrix<S, Eigen::Dynamic, 1>::Ones(3)));
  auto negative = c.learning_rates();
  negative(0) = S(-1);
  EXPECT_FALSE(c.set_learning_rates(negative));
  EXPECT_TRUE(state_of(c) == before);
}

// ----------------------------------------------------------- reference model

template <typename S>
Bytes state_of(const ReferenceModel<S>& r) {
  Bytes b;
  return b.add(r.eta_d()).add(r.nu_d()).add(r.desired().eta_d).add(r.desired().eta_d_dot)
      .add(r.desired().eta_d_ddot).value(r.pitch_limited());
}

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

// Zero or negative gains and time steps, for every controller's config.
TYPED_TEST(ReliabilityTest, ControllerConfigurationsRefuseZeroOrNegativeGainsAndDt) {
  using S = TypeParam;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  auto expect_field = [](const ValidationError& e, const char* field, const char* what) {
    ASSERT_FALSE(e.ok()) << what;
    EXPECT_STREQ(e.field, field) << what;
  };
  for (const S bad : {S(0), S(-1), nan}) {
    NNAdaptiveConfig<S> n;
    n.dt = bad;
    expect_field(validate(n), "dt", "NN dt");
    n = {};
    n.lambda(1) = bad;
    expect_field(validate(n), "lambda", "NN lambda");
    LinearAdaptiveConfig<S> l;
    l.dt = bad;
    expect_field(validate(l), "dt", "linear dt");
    l = {};
    l.lambda(5) = bad;
    expect_field(validate(l), "lambda", "linear lambda");
    PIDConfig<S> p;
    p.dt = bad;
    expect_field(validate(p), "dt", "PID dt");
    p = {};
    p.integral_limit(0) = bad;
    expect_field(validate(p), "integral_limit", "PID integral_limit");
    SlidingModeConfig<S> s;
    s.phi(2) = bad;
    expect_field(validate(s), "phi", "SMC phi");
    s = {};
    s.lambda(0) = bad;
    expect_field(validate(s), "lambda", "SMC lambda");
  }
  for (const S bad : {S(-1), nan, -std::numeric_limits<S>::infinity()}) {
    NNAdaptiveConfig<S> n;
    n.kd(4) = bad;
    expect_field(validate(n), "kd", "NN kd");
    n = {};
    n.gamma = bad;
    expect_field(validate(n), "gamma", "NN gamma");
    LinearAdaptiveConfig<S> l;
    l.gamma(7) = bad;
    expect_field(validate(l), "gamma", "linear gamma");
    PDConfig<S> d;
    d.kp(0) = bad;
    expect_field(validate(d), "kp", "PD kp");
    d = {};
    d.kd(5) = bad;
    expect_field(validate(d), "kd", "PD kd");
    PIDConfig<S> p;
    p.ki(2) = bad;
    expect_field(validate(p), "ki", "PID ki");
    SlidingModeConfig<S> s;
    s.k(1) = bad;
    expect_field(validate(s), "k", "SMC k");
  }
  ReferenceModel<S> r;
  EXPECT_STREQ(ReferenceModel<S>::create(Vector6<S>::Zero(), Vector6<S>::Ones(),
                                         Vector6<S>::Zero(), r)
                   .field,
               "lambda_d");
  EXPECT_STREQ(ReferenceModel<S>::create(Vector6<S>::Ones(), -Vector6<S>::Ones(),
                                         Vector6<S>::Zero(), r)
                   .field,
               "omega");
}

// Non-symmetric or indefinite mass matrices, in every way they can come about.
// An indefinite part may be named itself or as the sum M it spoils
// ("mass_matrix"); either names what is wrong.
TYPED_TEST(ReliabilityTest, VehicleRefusesNonSymmetricOrIndefiniteMassMatrices) {
  using S = TypeParam;
  struct Case {
    const char* what;
    void (*mutate)(VehicleParameters<S>&);
    const char* field;
    const char* or_field = nullptr;
  };
  const Case cases[] = {
      {"non-symmetric inertia", [](auto& p) { p.inertia(0, 2) = S(3); }, "inertia"},
      {"non-symmetric added mass", [](auto& p) { p.added_mass(5, 1) = S(-4); }, "added_mass"},
      {"negative definite added mass", [](auto& p) { p.added_mass *= S(-10); }, "added_mass",
       "mass_matrix"},
      {"indefinite inertia", [](auto& p) { p.inertia(1, 1) = S(-200); }, "inertia", "mass_matrix"},
      {"symmetric but indefinite coupling",
       [](auto& p) {
         p.added_mass(0, 1) = p.added_mass(1, 0) = S(1000);
       },
       "added_mass", "mass_matrix"},
      {"every part definite, M_RB + M_A not (r_g 1 m off)",
       [](auto& p) { p.centre_of_gravity.z() = S(1); }, "mass_matrix"},
      {"zero mass", [](auto& p) { p.mass = S(0); }, "mass"},
      {"negative mass", [](auto& p) { p.mass = S(-185); }, "mass"},
      {"NaN inertia", [](auto& p) { p.inertia(2, 2) = std::numeric_limits<S>::quiet_NaN(); },
       "inertia"},
      {"infinite added mass",
       [](auto& p) { p.added_mass(3, 3) = std::numeric_limits<S>::infinity(); }, "added_mass"},
  };
  for (const Case& c : cases) {
    VehicleParameters<S> p = nerov_parameters<S>();
    c.mutate(p);
    Vehicle<S> v;
    const ValidationError e = Vehicle<S>::create(p, v);
    ASSERT_FALSE(e.ok()) << c.what;
    const std::string field = e.field;
    EXPECT_TRUE(field == c.field || (c.or_field && field == c.or_field)) << c.what << ": " << field;
    EXPECT_FALSE(v.valid()) << c.what;
  }
}

// ----------------------------------------------------------------- thrusters

template <typename S>
ThrusterConfig<S> nerov_thrusters() {
  // The layout of vehicles/nerov.toml: columns [d; r x d].
  const double pos[6][3] = {{-0.5, 0.3, 0}, {-0.5, -0.3, 0}, {0.4, 0, 0},
                            {0.4, 0, 0},    {-0.4, 0.3, 0},  {-0.4, -0.3, 0}};
  const double dir[6][3] = {{1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  ThrusterConfig<S> c;
  c.matrix.resize(6, 6);
  for (int j = 0; j < 6; ++j) {
    const Eigen::Vector3d r(pos[j][0], pos[j][1], pos[j][2]), d(dir[j][0], dir[j][1], dir[j][2]);
    c.matrix.col(j) << d.cast<S>(), r.cross(d).cast<S>();
  }
  c.max_thrust = ThrusterConfig<S>::Vector::Constant(6, S(250));
  c.min_thrust = -c.max_thrust;
  return c;
}

// A finite but enormous demanded wrench (a controller fed a glitching sensor)
// must still give thrusts within their limits: never NaN, never beyond.
TYPED_TEST(ReliabilityTest, ThrusterCommandsStayWithinLimitsForHugeFiniteWrenches) {
  using S = TypeParam;
  for (const Saturation sat : {Saturation::scale, Saturation::clip}) {
    ThrusterConfig<S> cfg = nerov_thrusters<S>();
    cfg.saturation = sat;
    Thrusters<S> t;
    ASSERT_TRUE(Thrusters<S>::create(cfg, t).ok());
    for (int i = 0; i < 6; ++i)
      for (const S v : hostile_values<S>()) {
        if (!std::isfinite(v)) continue;
        for (const S other : {S(0), S(100), -std::numeric_limits<S>::max()}) {
          Vector6<S> tau = Vector6<S>::Constant(other);
          tau(i) = v;
          t.command(tau);
          t.advance(S(0.02));
          const std::string what = std::string(sat == Saturation::scale ? "scale" : "clip") +
                                   ", tau[" + std::to_string(i) + "] = " + show(v) +
                                   ", others " + show(other);
          EXPECT_TRUE(t.commanded().allFinite()) << what << ": " << t.commanded().transpose();
          EXPECT_TRUE((t.commanded().array() <= cfg.max_thrust.array()).all() &&
                      (t.commanded().array() >= cfg.min_thrust.array()).all())
              << what << ": " << t.commanded().transpose();
          EXPECT_TRUE(t.wrench().allFinite()) << what;
        }
      }
  }
}

TYPED_TEST(ReliabilityTest, ThrusterConfigurationNamesTheBadField) {
  using S = TypeParam;
  struct Case {
    const char* what;
    void (*mutate)(ThrusterConfig<S>&);
    const char* field;
  };
  const Case cases[] = {
      {"five thrusters", [](auto& c) { c.matrix.conservativeResize(6, 5); }, "thrusters.matrix"},
      {"NaN in B", [](auto& c) { c.matrix(2, 3) = std::numeric_limits<S>::quiet_NaN(); },
       "thrusters.matrix"},
      {"rank-deficient B", [](auto& c) { c.matrix.col(5) = c.matrix.col(4); },
       "thrusters.matrix"},
      {"limits of the wrong size", [](auto& c) { c.max_thrust.conservativeResize(5); },
       "thrusters.max_thrust"},
      {"min above max", [](auto& c) { c.min_thrust(1) = S(300); }, "thrusters.max_thrust"},
      {"infinite limit", [](auto& c) { c.max_thrust(0) = std::numeric_limits<S>::infinity(); },
       "thrusters.max_thrust"},
      {"zero weight",
       [](auto& c) {
         c.weights = ThrusterConfig<S>::Vector::Ones(6);
         c.weights(2) = S(0);
       },
       "thrusters.weights"},
      {"negative time constant", [](auto& c) { c.time_constant = S(-0.1); },
       "thrusters.time_constant"},
  };
  for (const Case& k : cases) {
    ThrusterConfig<S> cfg = nerov_thrusters<S>();
    k.mutate(cfg);
    Thrusters<S> t;
    const ValidationError e = Thrusters<S>::create(cfg, t);
    ASSERT_FALSE(e.ok()) << k.what;
    EXPECT_STREQ(e.field, k.field) << k.what;
  }
}

// -------------------------------------------------------------- closed loop

template <typename S>
SimulationConfig<S> loop_config() {
  SimulationConfig<S> c;
  c.duration = S(2);
  c.command.times.resize(1);
  c.command.times << S(0);
  c.command.poses.setZero(1, 6);
  c.command.poses(0, 0) = S(1);
  return c;
}

TYPED_TEST(ReliabilityTest, SimulationConfigurationNamesTheBadField) {
  using S = TypeParam;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  const Vehicle<S> vehicle(nerov_parameters<S>());
  struct Case {
    const char* what;
    std::function<void(SimulationConfig<S>&)> mutate;
    const char* field;
  };
  const std::vector<Case> cases = {
      {"zero dt", [](auto& c) { c.dt = S(0); }, "dt"},
      {"negative dt", [](auto& c) { c.dt = S(-0.2); }, "dt"},
      {"dt above kMaxStep", [](auto& c) { c.dt = S(10.5); }, "dt"},
      {"zero substeps", [](auto& c) { c.substeps = 0; }, "substeps"},
      {"negative duration", [](auto& c) { c.duration = S(-1); }, "duration"},
      {"too many steps", [](auto& c) { c.duration = S(1e9); }, "duration"},
      {"NaN initial pose", [nan](auto& c) { c.eta0(2) = nan; }, "eta0"},
      {"initial pitch at 90 deg", [](auto& c) { c.eta0(4) = static_cast<S>(kPi / 2); }, "eta0"},
      {"infinite initial velocity",
       [](auto& c) { c.nu0(5) = std::numeric_limits<S>::infinity(); }, "nu0"},
      {"no command",
       [](auto& c) {
         c.command.times.resize(0);
         c.command.poses.resize(0, 6);
       },
       "command.times"},
      {"times and poses mismatched", [](auto& c) { c.command.poses.setZero(2, 6); },
       "command.poses"},
      {"NaN commanded pose", [nan](auto& c) { c.command.poses(0, 3) = nan; }, "command.poses"},
      {"times not increasing",
       [](auto& c) {
         c.command.times.resize(2);
         c.command.times << S(1), S(1);
         c.command.poses.setZero(2, 6);
       },
       "command.times"},
      {"zero reference damping", [](auto& c) { c.lambda_d(0) = S(0); }, "lambda_d"},
      {"negative reference stiffness", [](auto& c) { c.omega(1) = S(-1); }, "omega"},
      {"disturbance in DOF 6", [](auto& c) { c.disturbances.push_back({6, S(1), S(0.1), S(0), S(0)}); },
       "disturbances.dof"},
      {"NaN disturbance amplitude",
       [nan](auto& c) { c.disturbances.push_back({5, nan, S(0.1), S(0), S(0)}); }, "disturbances"},
      {"negative noise", [](auto& c) { c.noise_nu(0) = S(-0.1); }, "noise_nu"},
      {"NaN current", [nan](auto& c) { c.current(0) = nan; }, "current"},
      {"sensor fault ending before it starts",
       [](auto& c) {
         SensorFault<S> f;
         f.start = S(2);
         f.end = S(1);
         c.sensor_faults.push_back(f);
       },
       "sensor_faults.end"},
      {"unknown sensor fault kind",
       [](auto& c) {
         SensorFault<S> f;
         f.kind = static_cast<SensorFaultKind>(7);
         f.end = S(1);
         c.sensor_faults.push_back(f);
       },
       "sensor_faults.kind"},
      {"current steps out of order",
       [](auto& c) {
         c.current_steps.push_back({S(5), Vector3<S>::Zero()});
         c.current_steps.push_back({S(4), Vector3<S>::Zero()});
       },
       "current_steps.time"},
      {"thruster failure without thrusters",
       [](auto& c) { c.failures.push_back({0, S(0), S(1)}); }, "thruster_failures"},
      {"thruster failure of thruster 6",
       [](auto& c) {
         c.use_thrusters = true;
         c.thrusters = nerov_thrusters<S>();
         c.failures.push_back({6, S(0), S(1)});
       },
       "thruster_failures.index"},
      {"efficiency above one",
       [](auto& c) {
         c.use_thrusters = true;
         c.thrusters = nerov_thrusters<S>();
         c.failures.push_back({0, S(1.5), S(1)});
       },
       "thruster_failures.efficiency"},
      {"bad thruster layout",
       [](auto& c) {
         c.use_thrusters = true;
         c.thrusters = nerov_thrusters<S>();
         c.thrusters.matrix.col(1).setZero();
       },
       "thrusters.matrix"},
  };
  for (const Case& k : cases) {
    SimulationConfig<S> cfg = loop_config<S>();
    k.mutate(cfg);
    PDController<S> ctl = pd<S>();
    SimulationResult<S> out;
    const ValidationError e = simulate(vehicle, ctl, cfg, out);
    ASSERT_FALSE(e.ok()) << k.what;
    EXPECT_STREQ(e.field, k.field) << k.what;
    EXPECT_EQ(out.steps, 0) << k.what;
  }
  PDController<S> ctl = pd<S>();
  SimulationResult<S> out;
  EXPECT_STREQ(simulate(Vehicle<S>{}, ctl, loop_config<S>(), out).field, "vehicle");
}

// The loop under a sensor dropout: every refused step is recorded with its
// status, the demanded tau is zero (policy "zero") or the last accepted one
// (policy "hold"), the plant never sees a NaN, and the controller's weights
// do not move while it is blind.
TYPED_TEST(ReliabilityTest, LoopReportsRefusedStepsAndKeepsTheWeightsDuringADropout) {
  using S = TypeParam;
  const Vehicle<S> vehicle(nerov_parameters<S>());
  for (const RefusedStepPolicy policy : {RefusedStepPolicy::zero, RefusedStepPolicy::hold}) {
    SimulationConfig<S> cfg = loop_config<S>();
    cfg.duration = S(20);
    cfg.refused_step_policy = policy;
    SensorFault<S> f;
    f.kind = SensorFaultKind::dropout;
    f.start = S(5);
    f.end = S(8);
    f.eta = false;  // only the velocity drops out
    cfg.sensor_faults.push_back(f);
    auto ctl = nn<S>(RobustModification::sigma, 9);
    SimulationResult<S> r;
    ASSERT_TRUE(simulate(vehicle, ctl, cfg, r).ok());
    ASSERT_FALSE(r.diverged);
    ASSERT_TRUE(r.eta.allFinite() && r.nu.allFinite() && r.tau_applied.allFinite());
    int refused = 0;
    for (Eigen::Index k = 0; k < r.steps; ++k) {
      const bool in_fault = r.t(k) >= f.start && r.t(k) < f.end;
      EXPECT_EQ(r.faults(k) == fault_bits::dropout, in_fault) << "t = " << r.t(k);
      EXPECT_EQ(r.controller_status(k) == static_cast<std::uint8_t>(Status::non_finite_input),
                in_fault)
          << "t = " << r.t(k);
      if (!in_fault) continue;
      ++refused;
      EXPECT_EQ(r.adaptive_norm(k), r.adaptive_norm(k - 1)) << "weights moved while blind";
      const Vector6<S> expected = policy == RefusedStepPolicy::zero
                                      ? Vector6<S>::Zero().eval()
                                      : Vector6<S>(r.tau_demanded.row(k - 1).transpose());
      EXPECT_TRUE((r.tau_demanded.row(k).transpose().array() == expected.array()).all())
          << "t = " << r.t(k);
    }
    EXPECT_GE(refused, 14);  // 3 s at 5 Hz, give or take the rounding of k dt
  }
}

}  // namespace
