// The Gymnasium tracking task's step (sim/tracking_task.hpp) over K rows
// touches no heap and is noexcept, in float and double; and its outcome
// rows say what the formulas say for rows inside and outside the box, a
// diverged row and a done one (tests/python/test_gym_task.py checks every
// entry against the formulas in numpy).
#include "alloc_probe.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

#include "neurov/sim/tracking_task.hpp"

namespace {

using namespace neurov;

NEUROV_SCALAR_SUITE(TrackingTaskAlloc);

constexpr std::size_t kRows = 4;

TYPED_TEST(TrackingTaskAlloc, StepRowsAllocateNothingAndScoreTheBoxAndTheEnd) {
  using S = TypeParam;
  TrackingTaskConfig<S> config;
  config.box_low = Vector3<S>(S(-10), S(-10), S(-2));
  config.box_high = Vector3<S>(S(10), S(10), S(8));
  config.action_positive = Eigen::Matrix<S, Eigen::Dynamic, 1>::Constant(8, S(40));
  config.action_negative = Eigen::Matrix<S, Eigen::Dynamic, 1>::Constant(8, S(30));  // asymmetric
  config.thrusters = Eigen::Matrix<S, 6, Eigen::Dynamic>::Constant(6, 8, S(0.5));
  config.dropouts_read_zero = true;
  TrackingTask<S> task;
  ASSERT_FALSE(TrackingTask<S>::create(config, task));

  std::array<S, 6 * kRows> eta{}, nu{}, eta_d{}, rate{}, accel{}, eta_true{}, tau{};
  std::array<S, 8 * kRows> actions{}, clipped_actions{};
  for (std::size_t i = 0; i < actions.size(); ++i) actions[i] = S(0.3) * S(int(i % 9) - 4);  // -1.2 .. 1.2
  for (std::size_t i = 0; i < eta.size(); ++i) rate[i] = accel[i] = S(0.1) * S(int(i % 5));
  eta[6 * 1 + 3] = std::numeric_limits<S>::quiet_NaN();  // a dropout, read as 0
  eta_true[6 * 1 + 5] = S(3.5);                         // an angle error past pi, wrapped
  eta_true[6 * 2 + 0] = S(11);                          // outside the box
  bool diverged[kRows] = {false, false, false, true}, done[kRows] = {false, true, false, true};
  bool clipped[kRows], terminated[kRows], truncated[kRows], outside[kRows];
  std::int64_t steps_left[kRows] = {5, 0, 7, 9};
  S reward[kRows];
  std::array<float, kTrackingObservationSize * kRows> observation{};
  TrackingRows<S> rows;
  rows.eta = eta.data();
  rows.nu = nu.data();
  rows.eta_d = eta_d.data();
  rows.eta_d_dot = rate.data();
  rows.eta_d_ddot = accel.data();
  rows.eta_true = eta_true.data();
  rows.actions = clipped_actions.data();
  rows.diverged = diverged;
  rows.done = done;
  rows.steps_left = steps_left;
  const TrackingScores<S> scores{reward, terminated, truncated, outside};
  static_assert(noexcept(clip_actions(kRows, 8, actions.data(), clipped_actions.data(), clipped)));
  static_assert(noexcept(tracking_forces(task, kRows, clipped_actions.data(), tau.data())));
  static_assert(noexcept(tracking_outcome(task, kRows, rows, observation.data(), scores)));

  std::ptrdiff_t bad = 0;
  const auto w = alloc_probe::watch([&] {
    bad = clip_actions(kRows, 8, actions.data(), clipped_actions.data(), clipped);
    tracking_forces(task, kRows, clipped_actions.data(), tau.data());
    tracking_outcome(task, kRows, rows, observation.data(), scores);
    alloc_probe::escape(observation.data());
  });
  EXPECT_EQ(w.new_calls, 0);
  EXPECT_EQ(w.eigen_failures, 0);
  ASSERT_EQ(bad, -1);

  EXPECT_TRUE(clipped[0]);  // -1.2 in row 0
  for (const S a : clipped_actions) EXPECT_LE(std::abs(a), S(1));
  // u = a 40 for a >= 0, a 30 below; tau_r = 0.5 sum_j u_j.
  S want = 0;
  for (int j = 0; j < 8; ++j) want += S(0.5) * clipped_actions[j] * (clipped_actions[j] >= 0 ? S(40) : S(30));
  EXPECT_NEAR(tau[0], want, S(1e-4) * std::abs(want) + S(1e-5));
  for (const float o : observation) EXPECT_TRUE(std::isfinite(o));  // the dropout read as 0
  EXPECT_NEAR(observation[kTrackingObservationSize * 1 + 24], 0.0F, 0.0F);
  EXPECT_FALSE(outside[0] || terminated[0] || truncated[0]);
  EXPECT_TRUE(truncated[1] && !terminated[1]);  // done inside the box
  EXPECT_TRUE(outside[2] && terminated[2] && !truncated[2]);
  EXPECT_TRUE(terminated[3] && !outside[3] && !truncated[3]);  // diverged and done: terminated
  const S pi = S(3.14159265358979323846);
  const S yaw = S(3.5) - 2 * pi;
  S effort = 0;
  for (int j = 8; j < 16; ++j) effort += clipped_actions[j] * clipped_actions[j];
  EXPECT_NEAR(reward[1], -(yaw * yaw + S(0.01) * effort), S(1e-5));
  // Ending early pays position_weight reach^2 per step not simulated.
  EXPECT_LT(reward[2], -task.termination_cost() * S(7));
  EXPECT_NEAR(task.termination_cost(), S(20 * 20 + 20 * 20 + 10 * 10), S(1e-3));
}

TYPED_TEST(TrackingTaskAlloc, ANonFiniteActionRowIsNamedAndNothingWritten) {
  using S = TypeParam;
  std::array<S, 12> a{}, out{};
  out.fill(S(7));
  bool clipped[2] = {true, true};
  a[8] = std::numeric_limits<S>::infinity();
  EXPECT_EQ(clip_actions(2, 6, a.data(), out.data(), clipped), 1);
  for (const S v : out) EXPECT_EQ(v, S(7));
  EXPECT_TRUE(clipped[0] && clipped[1]);
}

TYPED_TEST(TrackingTaskAlloc, TheValidatorNamesTheField) {
  using S = TypeParam;
  TrackingTaskConfig<S> c;
  c.box_high(1) = c.box_low(1);
  TrackingTask<S> task;
  const ValidationError e = TrackingTask<S>::create(c, task);
  ASSERT_TRUE(e);
  EXPECT_STREQ(e.field, "box_high");
  EXPECT_EQ(e.index, 1);
  c = TrackingTaskConfig<S>();
  c.action_negative.resize(5);
  c.action_negative.setOnes();
  EXPECT_STREQ(TrackingTask<S>::create(c, task).field, "action_negative");
}

}  // namespace
