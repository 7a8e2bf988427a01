// The NN controller refuses bad input (zero tau, weights unchanged byte for
// byte) and names the parameter of a bad configuration.
#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "controller_state.hpp"
#include "nn_reference.hpp"
#include "step_inputs.hpp"

namespace {

using namespace neurov;
using namespace neurov_test::nn;

NEUROV_SCALAR_SUITE(NNBadInputTest);

// ------------------------------------------------------------------ bad input

/// After a history, every bad input of step() is refused
/// (expect_bad_inputs_refused, on all the NN's state), and afterwards the
/// controller steps exactly as a twin that never saw the bad calls.
template <typename Ctl>
void expect_refuses_bad_inputs(Ctl ctl, Rng& rng) {
  using S = typename Ctl::Scalar;
  using V = Vector6<S>;
  V args[5];
  neurov_test::draw_step_inputs(rng, args);
  V tau;
  for (int i = 0; i < 2; ++i)  // a history, so "unchanged" means something
    ASSERT_EQ(ctl.step(args[0], args[1], args[2], args[3], args[4], tau), Status::ok);
  Ctl twin = ctl;
  neurov_test::expect_bad_inputs_refused(ctl, args, [](const Ctl& c) { return neurov_test::state_of(c); });
  V tau_twin;
  ASSERT_EQ(ctl.step(args[0], args[1], args[2], args[3], args[4], tau), Status::ok);
  ASSERT_EQ(twin.step(args[0], args[1], args[2], args[3], args[4], tau_twin), Status::ok);
  EXPECT_EQ(ctl.last_status(), Status::ok);
  EXPECT_TRUE(all_near(tau, tau_twin, 0.0));
  EXPECT_TRUE(neurov_test::state_of(ctl) == neurov_test::state_of(twin));
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
