// The longest step neurov integrates (kMaxStep, core/validation.hpp): a
// longer one is refused as invalid_argument and changes nothing, in rk4_step
// and ReferenceModel::step, where it used to return finite nonsense (1e43
// after 1e6 s) or be reported as a non-finite input.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "neurov/control/reference_model.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/integrator.hpp"
#include "neurov/model/vehicle.hpp"
#include "test_support.hpp"

namespace {

using neurov::DesiredState;
using neurov::ReferenceModel;
using neurov::Status;
using neurov::Vector6;
using neurov::Vehicle;

NEUROV_SCALAR_SUITE(StepBoundTest);

template <typename S>
S above_the_bound(int k) {
  const S values[] = {std::nextafter(S(neurov::kMaxStep), S(100)), S(10.5), S(1e6), S(1e30),
                      std::numeric_limits<S>::max()};
  return values[k];
}

TYPED_TEST(StepBoundTest, Rk4RefusesAStepAboveTheBoundAndKeepsTheState) {
  using S = TypeParam;
  const Vehicle<S> vehicle(neurov::nerov_parameters<S>());
  Vector6<S> tau;
  tau << S(100), S(0), S(50), S(0), S(0), S(5);
  const Vector6<S> eta0 = Vector6<S>::Constant(S(0.1)), nu0 = Vector6<S>::Constant(S(0.2));
  for (int k = 0; k < 5; ++k) {
    const S dt = above_the_bound<S>(k);
    Vector6<S> eta = eta0, nu = nu0;
    EXPECT_EQ(neurov::rk4_step(vehicle, eta, nu, tau, dt), Status::invalid_argument) << dt;
    EXPECT_TRUE((eta.array() == eta0.array()).all() && (nu.array() == nu0.array()).all()) << dt;
  }
  // The bound itself is a step.
  Vector6<S> eta = eta0, nu = nu0;
  EXPECT_NE(neurov::rk4_step(vehicle, eta, nu, tau, S(neurov::kMaxStep)),
            Status::invalid_argument);
}

TYPED_TEST(StepBoundTest, ReferenceModelRefusesAStepAboveTheBoundAndKeepsTheState) {
  using S = TypeParam;
  ReferenceModel<S> ref(Vector6<S>::Constant(S(1)), Vector6<S>::Constant(S(0.25)));
  Vector6<S> r = Vector6<S>::Zero();
  r(0) = S(1);
  DesiredState<S> good;
  ASSERT_EQ(ref.step(r, S(0.2), good), Status::ok);
  const Vector6<S> eta_d = ref.eta_d();
  for (int k = 0; k < 5; ++k) {
    const S dt = above_the_bound<S>(k);
    DesiredState<S> d;
    EXPECT_EQ(ref.step(r, dt, d), Status::invalid_argument) << dt;
    EXPECT_TRUE((d.eta_d.array() == good.eta_d.array()).all()) << dt;
    EXPECT_TRUE((ref.eta_d().array() == eta_d.array()).all()) << dt;
  }
  DesiredState<S> d;
  EXPECT_EQ(ref.step(r, S(neurov::kMaxStep), d), Status::ok);
}

TEST(StepBoundTest, TheCheckNamesTheFieldAndStatesTheBound) {
  EXPECT_TRUE(neurov::detail::check_step("dt", 0.2).ok());
  EXPECT_TRUE(neurov::detail::check_step("dt", neurov::kMaxStep).ok());
  for (double dt : {0.0, -1.0, 10.000001, 1e6, std::nan(""),
                    std::numeric_limits<double>::infinity()}) {
    const neurov::ValidationError e = neurov::detail::check_step("dt", dt);
    ASSERT_FALSE(e.ok()) << dt;
    EXPECT_STREQ(e.field, "dt");
    EXPECT_NE(std::string(e.expected).find("<= 10 s"), std::string::npos);
  }
}

}  // namespace
