// The computation delay of a run (control_delay): the force demanded at row k
// acts n control periods later, checked in the log and against an undelayed
// run driven with the shifted forces; bad delays are named errors.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "neurov/neurov.hpp"
#include "controller_state.hpp"
#include "held_command.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using namespace neurov_test;

NEUROV_SCALAR_SUITE(SimulatorTimingTest);

template <typename S>
SimulationConfig<S> hover(int delay, bool thrusters) {
  SimulationConfig<S> c;
  c.duration = S(8);
  c.command = held<S>(Vector6<S>::Zero());
  c.control_delay = delay;
  c.use_thrusters = thrusters;
  if (thrusters) {
    c.thrusters = nerov_thrusters<S>(S(60));
    c.thrusters.time_constant = S(0.15);
  }
  return c;
}

/// A force that differs in every row and every DOF.
template <typename S>
Vector6<S> force(Eigen::Index k) {
  const S t = S(k);
  Vector6<S> f;
  f << S(30) * std::sin(t / S(3)), S(-15) + t, S(8) * std::cos(t / S(5)), S(0.5), S(-1),
      S(2) * std::sin(t / S(7));
  return f;
}

template <typename S>
SimulationResult<S> run(const SimulationConfig<S>& c, int shift) {
  const Vehicle<S> vehicle(nerov_parameters<S>());
  Simulator<S> sim;
  EXPECT_TRUE(Simulator<S>::create(vehicle, c, sim).ok());
  while (!sim.done()) {
    const Eigen::Index k = sim.steps() - shift;
    EXPECT_EQ(sim.step(k >= 0 ? force<S>(k) : Vector6<S>::Zero().eval(), ControllerReport<S>{}),
              Status::ok);
  }
  return sim.result();
}

TYPED_TEST(SimulatorTimingTest, TheForceAppliedAtRowKIsTheOneDemandedAtRowKMinusN) {
  using S = TypeParam;
  for (int n : {1, 3, kMaxControlDelay}) {
    const SimulationResult<S> r = run(hover<S>(n, false), 0);
    ASSERT_EQ(r.steps, 41);
    for (Eigen::Index k = 0; k < r.steps; ++k) {
      const Vector6<S> expected =
          k >= n ? Vector6<S>(r.tau_demanded.row(k - n).transpose()) : Vector6<S>::Zero();
      EXPECT_EQ(r.tau_demanded.row(k).transpose(), force<S>(k)) << "n = " << n << ", k = " << k;
      // tau_applied is the mean over the substeps: equal up to its rounding.
      EXPECT_LE((r.tau_applied.row(k).transpose() - expected).norm(),
                S(64) * eps<S>() * (S(1) + expected.norm()))
          << "n = " << n << ", k = " << k;
    }
  }
}

// The independent reference: an undelayed run fed the forces shifted by n
// rows (zero before) moves the plant, thrusters included, exactly as the
// delayed run does.
TYPED_TEST(SimulatorTimingTest, ADelayedRunIsAnUndelayedRunWithShiftedForces) {
  using S = TypeParam;
  for (bool thrusters : {false, true}) {
    for (int n : {1, 2}) {
      const SimulationResult<S> delayed = run(hover<S>(n, thrusters), 0);
      const SimulationResult<S> shifted = run(hover<S>(0, thrusters), n);
      const std::string what = std::string(thrusters ? "thrusters" : "direct") + ", n = " +
                               std::to_string(n);
      EXPECT_EQ(delayed.eta, shifted.eta) << what;
      EXPECT_EQ(delayed.nu, shifted.nu) << what;
      EXPECT_EQ(delayed.tau_applied, shifted.tau_applied) << what;
      EXPECT_EQ(delayed.thrusts, shifted.thrusts) << what;
    }
  }
}

TYPED_TEST(SimulatorTimingTest, ZeroDelayIsTheDefaultAndResetEmptiesThePendingForces) {
  using S = TypeParam;
  EXPECT_EQ(SimulationConfig<S>().control_delay, 0);
  const Vehicle<S> vehicle(nerov_parameters<S>());
  Simulator<S> sim;
  ASSERT_TRUE(Simulator<S>::create(vehicle, hover<S>(2, false), sim).ok());
  while (!sim.done()) sim.step(force<S>(sim.steps()), ControllerReport<S>{});
  const SimulationResult<S> first = sim.result();
  sim.reset();
  while (!sim.done()) sim.step(force<S>(sim.steps()), ControllerReport<S>{});
  EXPECT_EQ(sim.result().eta, first.eta);
  EXPECT_EQ(sim.result().tau_applied, first.tau_applied);
}

TYPED_TEST(SimulatorTimingTest, ADelayOutsideZeroToTheMaximumIsANamedError) {
  using S = TypeParam;
  for (int n : {-1, kMaxControlDelay + 1}) {
    const ValidationError e = validate(hover<S>(n, false));
    ASSERT_FALSE(e.ok()) << n;
    EXPECT_STREQ(e.field, "control_delay");
    EXPECT_EQ(e.value, static_cast<double>(n));
  }
  EXPECT_TRUE(validate(hover<S>(kMaxControlDelay, false)).ok());
}

}  // namespace
