// The NN controller refuses bad input (zero tau, weights unchanged byte for
// byte) and names the parameter of a bad configuration.
#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "nn_reference.hpp"

namespace {

using namespace neurov;
using namespace neurov_test::nn;

NEUROV_SCALAR_SUITE(NNBadInputTest);

// ------------------------------------------------------------------ bad input

template <typename Derived>
void append_bytes(std::vector<unsigned char>& out, const Eigen::MatrixBase<Derived>& m) {
  const auto e = m.eval();
  const auto* p = reinterpret_cast<const unsigned char*>(e.data());
  out.insert(out.end(), p, p + sizeof(typename Derived::Scalar) * e.size());
}

template <typename T>
void append_value(std::vector<unsigned char>& out, const T& v) {
  const auto* p = reinterpret_cast<const unsigned char*>(&v);
  out.insert(out.end(), p, p + sizeof v);
}

template <typename S, int N>
std::vector<unsigned char> snapshot(const NNAdaptiveController<S, N>& c) {
  std::vector<unsigned char> b;
  append_bytes(b, c.weights());
  append_value(b, c.weight_norm());
  append_bytes(b, c.tracking().s);
  append_bytes(b, c.tracking().nu_r_dot);
  append_bytes(b, c.network_output());
  append_bytes(b, c.basis());
  append_bytes(b, c.learning_rates());
  append_value(b, c.adapted());
  return b;
}

const char* const kArgNames[5] = {"eta", "nu", "eta_d", "eta_d_dot", "eta_d_ddot"};

/// Every argument of step() with NaN, +Inf and -Inf in two positions, then
/// the pitch singularity: each call is refused with tau = 0 and the
/// controller's state untouched, and afterwards the controller steps exactly
/// as a twin that never saw the bad calls.
template <typename Ctl>
void expect_refuses_bad_inputs(Ctl ctl, Rng& rng) {
  using S = typename Ctl::Scalar;
  using V = Vector6<S>;
  V args[5];
  args[0] = rng.pose<S>(1.0);
  args[1] = rng.velocity<S>();
  args[2] = args[0] + rng.vec6<S>(-0.3, 0.3);
  args[3] = rng.vec6<S>(-0.5, 0.5);
  args[4] = rng.vec6<S>(-0.5, 0.5);
  V tau;
  for (int i = 0; i < 2; ++i)  // a history, so "unchanged" means something
    ASSERT_EQ(ctl.step(args[0], args[1], args[2], args[3], args[4], tau), Status::ok);
  Ctl twin = ctl;
  const auto before = snapshot(ctl);
  const S bad_values[3] = {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                           -std::numeric_limits<S>::infinity()};
  for (int a = 0; a < 5; ++a)
    for (const S bad : bad_values)
      for (const int index : {0, 4}) {
        V in[5] = {args[0], args[1], args[2], args[3], args[4]};
        in[a](index) = bad;
        tau.setConstant(S(7));
        const Status st = ctl.step(in[0], in[1], in[2], in[3], in[4], tau);
        EXPECT_EQ(st, Status::non_finite_input) << kArgNames[a] << "[" << index << "] = " << bad;
        EXPECT_EQ(ctl.last_status(), Status::non_finite_input);
        EXPECT_TRUE((tau.array() == S(0)).all()) << kArgNames[a];
        EXPECT_TRUE(snapshot(ctl) == before) << "state changed by a bad " << kArgNames[a];
      }
  for (const double pitch : {kPi / 2, -kPi / 2}) {
    V eta = args[0];
    eta(4) = static_cast<S>(pitch);
    tau.setConstant(S(7));
    EXPECT_EQ(ctl.step(eta, args[1], args[2], args[3], args[4], tau), Status::near_singularity);
    EXPECT_EQ(ctl.last_status(), Status::near_singularity);
    EXPECT_TRUE((tau.array() == S(0)).all());
    EXPECT_TRUE(snapshot(ctl) == before) << "state changed at the singularity";
  }
  V tau_twin;
  ASSERT_EQ(ctl.step(args[0], args[1], args[2], args[3], args[4], tau), Status::ok);
  ASSERT_EQ(twin.step(args[0], args[1], args[2], args[3], args[4], tau_twin), Status::ok);
  EXPECT_EQ(ctl.last_status(), Status::ok);
  EXPECT_TRUE(all_near(tau, tau_twin, 0.0));
  EXPECT_TRUE(snapshot(ctl) == snapshot(twin));
}

TYPED_TEST(NNBadInputTest, BadInputIsRefusedWithZeroTauAndUnchangedWeights) {
  using S = TypeParam;
  Rng rng(120);
  const NNCase c = random_case<S>(rng);
  expect_refuses_bad_inputs(make_nn<S>(c), rng);
  expect_refuses_bad_inputs(make_nn<S, 12>(c), rng);
  expect_refuses_bad_inputs(make_nn<S>(c, Modification::sigma(0.3)), rng);
}

// ---------------------------------------------------------- configuration

struct BadConfig {
  const char* field;
  std::function<void(NNAdaptiveConfig<double>&)> mutate;
};

std::vector<BadConfig> bad_nn_configs() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {
      {"lambda", [](auto& c) { c.lambda(2) = 0; }},
      {"lambda", [](auto& c) { c.lambda(0) = -1; }},
      {"lambda", [nan](auto& c) { c.lambda(5) = nan; }},
      {"kd", [](auto& c) { c.kd(3) = -0.5; }},
      {"gamma", [](auto& c) { c.gamma = -0.1; }},
      {"gamma", [nan](auto& c) { c.gamma = nan; }},
      {"dt", [](auto& c) { c.dt = 0; }},
      {"dt", [](auto& c) { c.dt = -0.2; }},
      {"dt", [](auto& c) { c.dt = std::numeric_limits<double>::infinity(); }},
      {"sigma_m",
       [](auto& c) {
         c.modification = RobustModification::sigma;
         c.sigma_m = 0;
       }},
      {"sigma_m", [](auto& c) { c.sigma_m = -1; }},
      {"kappa",
       [](auto& c) {
         c.modification = RobustModification::e_modification;
         c.kappa = 0;
       }},
      {"w_max",
       [](auto& c) {
         c.modification = RobustModification::projection;
         c.w_max = 0;
       }},
      {"dead_zone", [](auto& c) { c.dead_zone = -0.01; }},
      {"modification", [](auto& c) { c.modification = static_cast<RobustModification>(9); }},
  };
}

TYPED_TEST(NNBadInputTest, InvalidConfigurationNamesTheParameter) {
  using S = TypeParam;
  Rng rng(130);
  const NNCase c = random_case<S>(rng);
  const auto net = make_network<S>(c.centres, c.widths, c.weights);
  NNAdaptiveConfig<double> good;
  good.kd.setConstant(10);
  {
    NNAdaptiveController<S> out;
    ASSERT_TRUE(NNAdaptiveController<S>::create(net, cast_config<S>(good), out).ok());
  }
  for (const BadConfig& bad : bad_nn_configs()) {
    NNAdaptiveConfig<double> d = good;
    bad.mutate(d);
    const NNAdaptiveConfig<S> cfg = cast_config<S>(d);
    const ValidationError e = validate(cfg);
    ASSERT_FALSE(e.ok()) << bad.field;
    EXPECT_STREQ(e.field, bad.field);
    NNAdaptiveController<S> out;
    EXPECT_STREQ(NNAdaptiveController<S>::create(net, cfg, out).field, bad.field);
    EXPECT_FALSE(out.configured()) << "create() wrote into `out` on failure";
    try {
      NNAdaptiveController<S> thrown(net, cfg);
      ADD_FAILURE() << "no exception for a bad " << bad.field;
    } catch (const std::invalid_argument& ex) {
      EXPECT_NE(std::string(ex.what()).find(bad.field), std::string::npos) << ex.what();
    }
  }
  // A network that was never configured.
  NNAdaptiveController<S> out;
  EXPECT_STREQ(NNAdaptiveController<S>::create(typename NNAdaptiveController<S>::Network{},
                                               cast_config<S>(good), out)
                   .field,
               "network");
}

}  // namespace
