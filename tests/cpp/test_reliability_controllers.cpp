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
// entries; the test_reliability_*.cpp files are the exhaustive sweep that
// docs/reliability.md cites. This one: the controllers' steps and setters.

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
  {
    SCOPED_TRACE("ArduSub, position hold, BlueROV2 Heavy");
    ArduSubConfig<S> c;
    c.FRAME_CONFIG = S(2);
    c.mode = S(2);
    check(ArduSubController<S>(c), 22u);
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
  check_one_step(ArduSubController<S>{}, in, "ArduSub");
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

}  // namespace
