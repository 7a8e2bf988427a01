// The five inputs of a controller's step: drawn at random, and made bad to
// check what a refused step must keep (control/controller_base.hpp). Shared
// by the contract run over every controller and the NN's own test.
#pragma once

#include <limits>

#include <gtest/gtest.h>

#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "test_support.hpp"

namespace neurov_test {

/// The arguments of step(), in order, for messages.
inline const char* const kStepArguments[5] = {"eta", "nu", "eta_d", "eta_d_dot", "eta_d_ddot"};

/// eta, nu, eta_d, eta_d_dot and eta_d_ddot: a pose and a velocity, and a
/// desired pose near it.
template <typename S>
void draw_step_inputs(Rng& rng, neurov::Vector6<S> (&v)[5]) {
  v[0] = rng.pose<S>(1.0);
  v[1] = rng.velocity<S>();
  v[2] = v[0] + rng.vec6<S>(-0.3, 0.3);
  v[3] = rng.vec6<S>(-0.5, 0.5);
  v[4] = rng.vec6<S>(-0.5, 0.5);
}

/// Every argument of step() with NaN, +Inf and -Inf at two positions, then eta
/// at the pitch singularity, each around the valid args: every call is refused
/// with tau = 0 and its status recorded, and state(ctl) stays as it was.
template <typename Ctl, typename State>
void expect_bad_inputs_refused(Ctl& ctl, const neurov::Vector6<typename Ctl::Scalar> (&args)[5],
                               State state) {
  using S = typename Ctl::Scalar;
  using neurov::Status;
  const auto before = state(ctl);
  const S bad_values[3] = {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                           -std::numeric_limits<S>::infinity()};
  neurov::Vector6<S> tau;
  for (int a = 0; a < 5; ++a)
    for (const S bad : bad_values)
      for (const int index : {0, 4}) {
        neurov::Vector6<S> in[5] = {args[0], args[1], args[2], args[3], args[4]};
        in[a](index) = bad;
        tau.setConstant(S(7));
        EXPECT_EQ(ctl.step(in[0], in[1], in[2], in[3], in[4], tau), Status::non_finite_input)
            << kStepArguments[a] << "[" << index << "] = " << bad;
        EXPECT_EQ(ctl.last_status(), Status::non_finite_input);
        EXPECT_TRUE((tau.array() == S(0)).all()) << kStepArguments[a];
        EXPECT_TRUE(state(ctl) == before) << "state changed by a bad " << kStepArguments[a];
      }
  for (const double pitch : {kPi / 2, -kPi / 2}) {
    neurov::Vector6<S> eta = args[0];
    eta(4) = static_cast<S>(pitch);
    tau.setConstant(S(7));
    EXPECT_EQ(ctl.step(eta, args[1], args[2], args[3], args[4], tau), Status::near_singularity);
    EXPECT_EQ(ctl.last_status(), Status::near_singularity);
    EXPECT_TRUE((tau.array() == S(0)).all());
    EXPECT_TRUE(state(ctl) == before) << "state changed at the singularity";
  }
}

}  // namespace neurov_test
