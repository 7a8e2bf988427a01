// The contract every controller keeps (control/controller_base.hpp), run over
// every controller type in float and double: a refused step writes tau = 0
// and changes nothing, NaN/Inf inputs and the pitch singularity are refused,
// accepted steps give a finite tau, reset() returns to the state create()
// left, the DesiredState overload is the 5-vector step, an unconfigured
// controller refuses, and the diagnostics hook reports the controller's own
// memory. A new controller joins by one line in Controllers and a draw_gains.
// (test_reliability_*.cpp sweep every hostile value through every entry.)
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "neurov/neurov.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::kPi;
using neurov_test::Rng;

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
/// PD, sliding mode and computed torque keep none.
template <typename Ctl>
typename Ctl::Scalar memory(const Ctl&) {
  return 0;
}

template <typename Ctl>
class ControllerContract : public ::testing::Test {};
using Controllers =
    ::testing::Types<PDController<float>, PDController<double>, PIDController<float>,
                     PIDController<double>, SlidingModeController<float>,
                     SlidingModeController<double>, LinearAdaptiveController<float>,
                     LinearAdaptiveController<double>, NNAdaptiveController<float>,
                     NNAdaptiveController<double>, NNAdaptiveController<float, 8>,
                     ComputedTorqueController<float>, ComputedTorqueController<double>>;
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

template <typename S>
void draw(Rng& rng, Vector6<S> (&v)[5]) {
  v[0] = rng.pose<S>(1.0);
  v[1] = rng.velocity<S>();
  v[2] = v[0] + rng.vec6<S>(-0.3, 0.3);
  v[3] = rng.vec6<S>(-0.5, 0.5);
  v[4] = rng.vec6<S>(-0.5, 0.5);
}

template <typename Ctl, typename S>
Status step(Ctl& c, const Vector6<S> (&v)[5], Vector6<S>& tau) {
  return c.step(v[0], v[1], v[2], v[3], v[4], tau);
}

template <typename S>
bool same_bits(const Vector6<S>& a, const Vector6<S>& b) {
  return std::memcmp(a.data(), b.data(), sizeof(S) * 6) == 0;
}

const char* const kArg[5] = {"eta", "nu", "eta_d", "eta_d_dot", "eta_d_ddot"};

// ------------------------------------------------------------------- tests

TYPED_TEST(ControllerContract, RefusedStepWritesZeroAndChangesNothing) {
  using Ctl = TypeParam;
  using S = typename Ctl::Scalar;
  Rng rng(700);
  Ctl ctl = make<Ctl>(rng);
  Vector6<S> args[5], tau;
  for (int k = 0; k < 3; ++k) {  // a history, so "unchanged" means something
    draw(rng, args);
    ASSERT_EQ(step(ctl, args, tau), Status::ok);
  }
  Ctl twin = ctl;
  const auto before = observable(ctl);
  const S bad_values[3] = {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                           -std::numeric_limits<S>::infinity()};
  for (int a = 0; a < 5; ++a)
    for (const S bad : bad_values)
      for (const int index : {0, 4}) {
        Vector6<S> in[5] = {args[0], args[1], args[2], args[3], args[4]};
        in[a](index) = bad;
        tau.setConstant(S(7));
        EXPECT_EQ(step(ctl, in, tau), Status::non_finite_input) << kArg[a] << "[" << index << "]";
        EXPECT_EQ(ctl.last_status(), Status::non_finite_input);
        EXPECT_TRUE((tau.array() == S(0)).all()) << kArg[a];
        EXPECT_TRUE(observable(ctl) == before) << "state changed by a bad " << kArg[a];
      }
  for (const double pitch : {kPi / 2, -kPi / 2}) {
    Vector6<S> in[5] = {args[0], args[1], args[2], args[3], args[4]};
    in[0](4) = static_cast<S>(pitch);
    tau.setConstant(S(7));
    EXPECT_EQ(step(ctl, in, tau), Status::near_singularity);
    EXPECT_TRUE((tau.array() == S(0)).all());
    EXPECT_TRUE(observable(ctl) == before) << "state changed at the singularity";
  }
  // Whatever a refusal might have touched unobserved shows in the next steps.
  for (int k = 0; k < 3; ++k) {
    draw(rng, args);
    Vector6<S> tau_twin;
    ASSERT_EQ(step(ctl, args, tau), Status::ok);
    ASSERT_EQ(step(twin, args, tau_twin), Status::ok);
    EXPECT_TRUE(same_bits(tau, tau_twin)) << "step " << k;
  }
  EXPECT_TRUE(observable(ctl) == observable(twin));
}

TYPED_TEST(ControllerContract, AcceptedStepsGiveFiniteTauAndFiniteState) {
  using Ctl = TypeParam;
  using S = typename Ctl::Scalar;
  Rng rng(701);
  Ctl ctl = make<Ctl>(rng);
  Vector6<S> args[5], tau;
  for (int k = 0; k < neurov_test::kPoints; ++k) {
    draw(rng, args);
    ASSERT_EQ(step(ctl, args, tau), Status::ok) << k;
    EXPECT_EQ(ctl.last_status(), Status::ok);
    EXPECT_TRUE(tau.allFinite()) << k;
    EXPECT_TRUE(ctl.tracking().s.allFinite());
    EXPECT_TRUE(ctl.logged_parameters().allFinite());
    EXPECT_TRUE(std::isfinite(ctl.adaptive_norm()));
  }
}

TYPED_TEST(ControllerContract, ResetReturnsToTheStateCreateLeft) {
  using Ctl = TypeParam;
  using S = typename Ctl::Scalar;
  Rng rng(702);
  const Ctl fresh = make<Ctl>(rng);
  Ctl ctl = fresh;
  Vector6<S> args[5], tau, tau_fresh;
  for (int k = 0; k < 10; ++k) {
    draw(rng, args);
    ASSERT_EQ(step(ctl, args, tau), Status::ok);
  }
  ctl.reset();
  EXPECT_EQ(ctl.last_status(), Status::ok);
  EXPECT_TRUE(ctl.tracking().s.isZero(S(0)));
  EXPECT_TRUE(observable(ctl) == observable(fresh));
  Ctl again = fresh;
  for (int k = 0; k < 3; ++k) {
    draw(rng, args);
    ASSERT_EQ(step(ctl, args, tau), Status::ok);
    ASSERT_EQ(step(again, args, tau_fresh), Status::ok);
    EXPECT_TRUE(same_bits(tau, tau_fresh)) << "step " << k;
  }
}

TYPED_TEST(ControllerContract, DesiredStateOverloadIsTheFiveVectorStep) {
  using Ctl = TypeParam;
  using S = typename Ctl::Scalar;
  Rng rng(703);
  Ctl a = make<Ctl>(rng);
  Ctl b = a;
  Vector6<S> args[5], tau_a, tau_b;
  for (int k = 0; k < 5; ++k) {
    draw(rng, args);
    DesiredState<S> d;
    d.eta_d = args[2];
    d.eta_d_dot = args[3];
    d.eta_d_ddot = args[4];
    ASSERT_EQ(step(a, args, tau_a), Status::ok);
    ASSERT_EQ(b.step(args[0], args[1], d, tau_b), Status::ok);
    EXPECT_TRUE(same_bits(tau_a, tau_b));
  }
}

TYPED_TEST(ControllerContract, UnconfiguredControllerRefusesEveryStep) {
  using Ctl = TypeParam;
  using S = typename Ctl::Scalar;
  Rng rng(704);
  Ctl ctl;
  EXPECT_FALSE(ctl.configured());
  Vector6<S> args[5], tau;
  draw(rng, args);
  tau.setConstant(S(3));
  EXPECT_EQ(step(ctl, args, tau), Status::invalid_argument);
  EXPECT_EQ(ctl.last_status(), Status::invalid_argument);
  EXPECT_TRUE((tau.array() == S(0)).all());
}

TYPED_TEST(ControllerContract, AdaptiveNormIsTheControllersOwnMemory) {
  using Ctl = TypeParam;
  using S = typename Ctl::Scalar;
  Rng rng(705);
  Ctl ctl = make<Ctl>(rng);
  Vector6<S> args[5], tau;
  for (int k = 0; k < 5; ++k) {
    draw(rng, args);
    ASSERT_EQ(step(ctl, args, tau), Status::ok);
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
