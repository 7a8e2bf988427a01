// The contract every controller keeps (control/controller_base.hpp), run over
// every controller type in float and double: a refused step writes tau = 0
// and changes nothing, NaN/Inf inputs and the pitch singularity are refused,
// accepted steps give a finite tau, reset() returns to the state create()
// left, the DesiredState overload is the 5-vector step, an unconfigured
// controller refuses, and the diagnostics hook reports the controller's own
// memory. Every controller of the C++ list (BuiltInControllers) is in it; one
// whose defaults are not a working configuration has a draw_gains.
// (test_reliability_*.cpp sweep every hostile value through every entry.)
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "neurov/neurov.hpp"
#include "step_inputs.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::draw_step_inputs;
using neurov_test::expect_bad_inputs_refused;
using neurov_test::Rng;
using neurov_test::same_bits;

// ------------------------------------------------- a configured controller

// Each controller is made from gains drawn from rng (draw_gains on its
// Config); memory() is the part of its state a step changes.

template <typename S>
void draw_gains(PDConfig<S>& c, Rng& rng) {
  c.kp = rng.vec6<S>(10, 100);
  c.kd = rng.vec6<S>(10, 200);
}

template <typename S>
void draw_gains(PIDConfig<S>& c, Rng& rng) {
  c.kp = rng.vec6<S>(10, 100);
  c.ki = rng.vec6<S>(1, 10);
  c.kd = rng.vec6<S>(10, 200);
}

template <typename S>
void draw_gains(SlidingModeConfig<S>& c, Rng& rng) {
  c.kd = rng.vec6<S>(10, 200);
  c.k = rng.vec6<S>(1, 20);
  c.phi.setConstant(S(0.1));
  EXPECT_TRUE(regressor_parameters(nerov_parameters<S>(), c.theta).ok());
}

template <typename S>
void draw_gains(LinearAdaptiveConfig<S>& c, Rng& rng) {
  c.kd = rng.vec6<S>(10, 200);
  c.gamma.setConstant(S(2));
  ParameterVector<S> theta;
  EXPECT_TRUE(regressor_parameters(nerov_parameters<S>(), theta).ok());
  c.theta0 = S(0.8) * theta;
}

template <typename S>
void draw_gains(ComputedTorqueConfig<S>& c, Rng& rng) {
  c.kd = rng.vec6<S>(10, 200);
  c.vehicle = neurov_test::random_vehicle_parameters<S>(rng, CoriolisForm::kirchhoff);
}

template <typename S>
void draw_gains(NNAdaptiveConfig<S>& c, Rng& rng) {
  c.kd = rng.vec6<S>(10, 200);
  c.gamma = S(2);
  c.modification = RobustModification::sigma;
  c.sigma_m = S(0.1);
}

template <typename Config, typename = void>
struct has_theta : std::false_type {};
template <typename Config>
struct has_theta<Config, std::void_t<decltype(Config::theta)>> : std::true_type {};
template <typename Config, typename = void>
struct has_kd : std::false_type {};
template <typename Config>
struct has_kd<Config, std::void_t<decltype(Config::kd)>> : std::true_type {};

/// Any other controller: its defaults, with K_d drawn and the nominal model
/// set when it has them.
template <typename Config>
void draw_gains(Config& c, Rng& rng) {
  if constexpr (has_kd<Config>::value) c.kd = rng.vec6<typename decltype(c.kd)::Scalar>(10, 200);
  if constexpr (has_theta<Config>::value) {
    using S = typename decltype(c.theta)::Scalar;
    EXPECT_TRUE(regressor_parameters(nerov_parameters<S>(), c.theta).ok());
  }
}

template <typename Ctl>
Ctl make(Rng& rng) {
  typename Ctl::Config c;
  if constexpr (std::is_constructible_v<Ctl, const typename Ctl::Config&>) {
    draw_gains(c, rng);
    return Ctl(c);
  } else {  // the NN controller, on a network of centres drawn first
    using S = typename Ctl::Scalar;
    const int n = Ctl::Network::kCentres == Eigen::Dynamic ? 12 : Ctl::Network::kCentres;
    typename Ctl::Network::CentreMatrix centres(n, kNNInputs);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < kNNInputs; ++i) centres(j, i) = rng.uniform<S>(-1.5, 1.5);
    typename Ctl::Network net;
    EXPECT_TRUE(Ctl::Network::create(centres, Ctl::BasisVector::Constant(n, S(2)), net).ok());
    draw_gains(c, rng);
    return Ctl(net, c);
  }
}

template <typename S>
S memory(const PIDController<S>& c) {
  return c.integral().norm();
}
template <typename S>
S memory(const LinearAdaptiveController<S>& c) {
  return c.theta().norm();
}
template <typename S, int N>
S memory(const NNAdaptiveController<S, N>& c) {
  return c.weights().norm();
}
/// ArduSub's memory: its PID integrators (attitude rates, vertical velocity
/// and acceleration, horizontal velocity).
template <typename S>
S memory(const ArduSubController<S>& c) {
  const auto& s = c.internals();
  S sum = s.vel_z.integrator * s.vel_z.integrator + s.accel_z.integrator * s.accel_z.integrator;
  for (int i = 0; i < 3; ++i) sum += s.rate[i].integrator * s.rate[i].integrator;
  for (int i = 0; i < 2; ++i) sum += s.vel_xy[i].integrator * s.vel_xy[i].integrator;
  return std::sqrt(sum);
}
template <typename Ctl, typename = void>
struct has_state_name : std::false_type {};
template <typename Ctl>
struct has_state_name<Ctl, std::void_t<decltype(Ctl::kStateName)>> : std::true_type {};

/// A controller with a named (6,) state remembers it; PD, sliding mode and
/// computed torque keep none.
template <typename Ctl>
typename Ctl::Scalar memory(const Ctl& c) {
  if constexpr (has_state_name<Ctl>::value)
    return c.state().norm();
  else
    return 0;
}

template <typename Ctl>
class ControllerContract : public ::testing::Test {};
// Every built-in controller in float and double, and the NN with a fixed
// number of centres.
template <typename... F, typename... D>
::testing::Types<F..., D..., NNAdaptiveController<float, 8>> contract_types(TypeList<F...>,
                                                                           TypeList<D...>);
using Controllers =
    decltype(contract_types(BuiltInControllers<float>{}, BuiltInControllers<double>{}));
TYPED_TEST_SUITE(ControllerContract, Controllers);

// ------------------------------------------------------------ observations

/// Bytes of what every controller exposes through the shared interface.
template <typename Ctl>
std::vector<unsigned char> observable(const Ctl& c) {
  std::vector<unsigned char> b;
  const auto add = [&b](const auto& m) {
    const auto e = m.eval();
    const auto* p = reinterpret_cast<const unsigned char*>(e.data());
    b.insert(b.end(), p, p + sizeof(typename Ctl::Scalar) * static_cast<size_t>(e.size()));
  };
  const auto& t = c.tracking();
  add(t.eta_tilde);
  add(t.eta_tilde_dot);
  add(t.s);
  add(t.eta_r_dot);
  add(t.eta_r_ddot);
  add(t.nu_r);
  add(t.nu_r_dot);
  add(c.logged_parameters());
  const typename Ctl::Scalar norm = c.adaptive_norm();
  const auto* p = reinterpret_cast<const unsigned char*>(&norm);
  b.insert(b.end(), p, p + sizeof norm);
  return b;
}

template <typename Ctl, typename S>
Status step(Ctl& c, const Vector6<S> (&v)[5], Vector6<S>& tau) {
  return c.step(v[0], v[1], v[2], v[3], v[4], tau);
}

/// A controller with gains drawn from the test's own stream, which then draws
/// the inputs of its steps: args are the last drawn, tau the last output.
template <typename Ctl>
struct UnderTest {
  using S = typename Ctl::Scalar;

  explicit UnderTest(std::uint32_t seed) : rng(seed), ctl(make<Ctl>(rng)) {}

  /// c (ctl or a copy of it) steps on newly drawn inputs.
  Status step_on_new_inputs(Ctl& c) {
    draw_step_inputs(rng, args);
    return step(c, args, tau);
  }

  /// n accepted steps of ctl: a history, so "unchanged" means something.
  ::testing::AssertionResult history(int n) {
    for (int k = 0; k < n; ++k)
      if (const Status st = step_on_new_inputs(ctl); st != Status::ok)
        return ::testing::AssertionFailure() << "step " << k << " of the history: " << to_string(st);
    return ::testing::AssertionSuccess();
  }

  Rng rng;
  Ctl ctl;
  Vector6<S> args[5], tau;
};

// ------------------------------------------------------------------- tests

TYPED_TEST(ControllerContract, RefusedStepWritesZeroAndChangesNothing) {
  using Ctl = TypeParam;
  using S = typename Ctl::Scalar;
  UnderTest<Ctl> t(700);
  ASSERT_TRUE(t.history(3));
  Ctl twin = t.ctl;
  expect_bad_inputs_refused(t.ctl, t.args, observable<Ctl>);
  // Whatever a refusal might have touched unobserved shows in the next steps.
  for (int k = 0; k < 3; ++k) {
    Vector6<S> tau_twin;
    ASSERT_EQ(t.step_on_new_inputs(t.ctl), Status::ok);
    ASSERT_EQ(step(twin, t.args, tau_twin), Status::ok);
    EXPECT_TRUE(same_bits(t.tau, tau_twin)) << "step " << k;
  }
  EXPECT_TRUE(observable(t.ctl) == observable(twin));
}

TYPED_TEST(ControllerContract, AcceptedStepsGiveFiniteTauAndFiniteState) {
  UnderTest<TypeParam> t(701);
  for (int k = 0; k < neurov_test::kPoints; ++k) {
    ASSERT_EQ(t.step_on_new_inputs(t.ctl), Status::ok) << k;
    EXPECT_EQ(t.ctl.last_status(), Status::ok);
    EXPECT_TRUE(t.tau.allFinite()) << k;
    EXPECT_TRUE(t.ctl.tracking().s.allFinite());
    EXPECT_TRUE(t.ctl.logged_parameters().allFinite());
    EXPECT_TRUE(std::isfinite(t.ctl.adaptive_norm()));
  }
}

TYPED_TEST(ControllerContract, ResetReturnsToTheStateCreateLeft) {
  using Ctl = TypeParam;
  using S = typename Ctl::Scalar;
  UnderTest<Ctl> t(702);
  const Ctl fresh = t.ctl;
  ASSERT_TRUE(t.history(10));
  t.ctl.reset();
  EXPECT_EQ(t.ctl.last_status(), Status::ok);
  EXPECT_TRUE(t.ctl.tracking().s.isZero(S(0)));
  EXPECT_TRUE(observable(t.ctl) == observable(fresh));
  Ctl again = fresh;
  for (int k = 0; k < 3; ++k) {
    Vector6<S> tau_fresh;
    ASSERT_EQ(t.step_on_new_inputs(t.ctl), Status::ok);
    ASSERT_EQ(step(again, t.args, tau_fresh), Status::ok);
    EXPECT_TRUE(same_bits(t.tau, tau_fresh)) << "step " << k;
  }
}

TYPED_TEST(ControllerContract, DesiredStateOverloadIsTheFiveVectorStep) {
  using Ctl = TypeParam;
  using S = typename Ctl::Scalar;
  UnderTest<Ctl> t(703);
  Ctl b = t.ctl;
  for (int k = 0; k < 5; ++k) {
    ASSERT_EQ(t.step_on_new_inputs(t.ctl), Status::ok);
    DesiredState<S> d;
    d.eta_d = t.args[2];
    d.eta_d_dot = t.args[3];
    d.eta_d_ddot = t.args[4];
    Vector6<S> tau_b;
    ASSERT_EQ(b.step(t.args[0], t.args[1], d, tau_b), Status::ok);
    EXPECT_TRUE(same_bits(t.tau, tau_b));
  }
}

TYPED_TEST(ControllerContract, UnconfiguredControllerRefusesEveryStep) {
  using Ctl = TypeParam;
  using S = typename Ctl::Scalar;
  Rng rng(704);
  Ctl ctl;
  EXPECT_FALSE(ctl.configured());
  Vector6<S> args[5], tau;
  draw_step_inputs(rng, args);
  tau.setConstant(S(3));
  EXPECT_EQ(step(ctl, args, tau), Status::invalid_argument);
  EXPECT_EQ(ctl.last_status(), Status::invalid_argument);
  EXPECT_TRUE((tau.array() == S(0)).all());
}

TYPED_TEST(ControllerContract, AdaptiveNormIsTheControllersOwnMemory) {
  using Ctl = TypeParam;
  using S = typename Ctl::Scalar;
  UnderTest<Ctl> t(705);
  Ctl& ctl = t.ctl;
  for (int k = 0; k < 5; ++k) {
    ASSERT_EQ(t.step_on_new_inputs(ctl), Status::ok);
    const S expected = memory(ctl);
    EXPECT_NEAR(static_cast<double>(ctl.adaptive_norm()), static_cast<double>(expected),
                1e-5 * (1.0 + static_cast<double>(expected)));
  }
  // Only the linear adaptive controller logs its parameters: theta_hat.
  if constexpr (std::is_same_v<Ctl, LinearAdaptiveController<S>>) {
    static_assert(Ctl::kLoggedParameters == kRegressorParameters);
    EXPECT_TRUE(ctl.logged_parameters() == ctl.theta());
  } else {
    static_assert(Ctl::kLoggedParameters == 0);
    EXPECT_EQ(ctl.logged_parameters().size(), 0);
  }
}

}  // namespace
