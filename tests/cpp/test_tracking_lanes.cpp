// The tracking task over runs (sim/tracking_lanes.hpp): a batch step gives
// each stepped lane the step of the same run alone, scores a lane it did not
// step as nothing, gives the same on two threads as on one, and steps on
// past a full log window.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "neurov/model/vehicle.hpp"
#include "neurov/sim/tracking_lanes.hpp"
#include "noisy_run.hpp"

namespace {

using namespace neurov;
using neurov_test::noisy_run;


/// What a step of K lanes writes, with the readout pointing at it.
struct Outcome {
  explicit Outcome(std::size_t k)
      : eta(6 * k), nu(6 * k), eta_d(6 * k), eta_d_dot(6 * k), eta_d_ddot(6 * k), eta_true(6 * k), reward(k),
        steps_left(k), statuses(k), observation(kTrackingObservationSize * k), flags(new bool[5 * k]()) {
    lanes.eta = eta.data();
    lanes.nu = nu.data();
    lanes.eta_d = eta_d.data();
    lanes.eta_d_dot = eta_d_dot.data();
    lanes.eta_d_ddot = eta_d_ddot.data();
    lanes.eta_true = eta_true.data();
    lanes.steps_left = steps_left.data();
    lanes.diverged = &flags[0];
    lanes.done = &flags[k];
    scores = {reward.data(), &flags[2 * k], &flags[3 * k], &flags[4 * k]};
  }
  std::vector<double> eta, nu, eta_d, eta_d_dot, eta_d_ddot, eta_true, reward;
  std::vector<std::int64_t> steps_left;
  std::vector<std::uint8_t> statuses;
  std::vector<float> observation;
  std::unique_ptr<bool[]> flags;  ///< diverged, done, terminated, truncated, outside: k each
  LaneReadout<double> lanes;
  TrackingScores<double> scores;
};

TrackingTask<double> task() {
  TrackingTask<double> t;
  EXPECT_FALSE(TrackingTask<double>::create(TrackingTaskConfig<double>{}, t));
  return t;
}

/// K actions in [-1, 1], row i differing.
std::vector<double> actions(std::size_t k) {
  std::vector<double> a(6 * k);
  for (std::size_t j = 0; j < a.size(); ++j) a[j] = 0.1 * static_cast<double>(int(j % 21) - 10);
  return a;
}

TEST(TrackingLanes, AStepOfABatchIsEachRunAloneAndALaneNotSteppedScoresNothing) {
  const Vehicle<double> nerov(nerov_parameters<double>());
  const std::size_t k = 3;
  std::vector<SimulationConfig<double>> configs = {noisy_run(1), noisy_run(2), noisy_run(3)};
  BatchSimulator<double> batch;
  ASSERT_FALSE(BatchSimulator<double>::create(std::vector<Vehicle<double>>(k, nerov), configs, batch));
  const TrackingTask<double> t = task();
  const std::vector<double> a = actions(k);
  const bool mask[k] = {true, false, true};
  Outcome got(k);
  tracking_step_batch(t, batch, a.data(), mask, got.statuses.data(), got.lanes, got.observation.data(), got.scores);

  for (std::size_t i = 0; i < k; ++i) {
    Simulator<double> alone;
    ASSERT_FALSE(Simulator<double>::create(nerov, configs[i], alone));
    Outcome want(1);
    if (mask[i]) {
      want.statuses[0] = static_cast<std::uint8_t>(
          tracking_step(t, alone, a.data() + 6 * i, want.lanes, want.observation.data(), want.scores));
    } else {
      tracking_observe(t, 1, [&](std::size_t) -> const Simulator<double>& { return alone; }, want.lanes,
                       want.observation.data());
      want.statuses[0] = kLaneNotStepped;
    }
    EXPECT_EQ(got.statuses[i], want.statuses[0]) << i;
    EXPECT_EQ(batch.lane(i).steps(), mask[i] ? 1 : 0) << i;
    EXPECT_EQ(0, std::memcmp(got.observation.data() + kTrackingObservationSize * i, want.observation.data(),
                             sizeof(float) * kTrackingObservationSize))
        << i;
    EXPECT_EQ(0, std::memcmp(got.eta_true.data() + 6 * i, want.eta_true.data(), sizeof(double) * 6)) << i;
    EXPECT_EQ(got.reward[i], mask[i] ? want.reward[0] : 0.0) << i;
    if (mask[i]) {
      EXPECT_LT(got.reward[i], 0.0) << i;  // a stepped lane pays for its effort
    }
    for (int f = 2; f < 5; ++f) EXPECT_EQ(got.flags[f * k + i], mask[i] && want.flags[f]) << i << " " << f;
  }
}

TEST(TrackingLanes, TwoThreadsGiveTheResultsOfOne) {
  const Vehicle<double> nerov(nerov_parameters<double>());
  const std::size_t k = 2 * kMinLanesPerThread;
  std::vector<SimulationConfig<double>> configs;
  for (std::size_t i = 0; i < k; ++i) configs.push_back(noisy_run(i + 1));
  const std::vector<Vehicle<double>> vehicles(k, nerov);
  const TrackingTask<double> t = task();
  const std::vector<double> a = actions(k);
  std::vector<Outcome> out;
  out.reserve(2);
  for (const unsigned threads : {1u, 2u}) {
    BatchSimulator<double> batch;
    ASSERT_FALSE(BatchSimulator<double>::create(vehicles, configs, batch));
    out.emplace_back(k);
    Outcome& o = out.back();
    tracking_step_batch(t, batch, a.data(), nullptr, o.statuses.data(), o.lanes, o.observation.data(), o.scores,
                        threads);
  }
  EXPECT_EQ(out[0].statuses, out[1].statuses);
  EXPECT_EQ(out[0].observation, out[1].observation);
  EXPECT_EQ(out[0].reward, out[1].reward);
  EXPECT_EQ(out[0].eta_true, out[1].eta_true);
}

TEST(TrackingLanes, ALogWindowIsEmptiedSoThatTheLanesStepOn) {
  const Vehicle<double> nerov(nerov_parameters<double>());
  BatchSimulator<double> batch;
  ASSERT_FALSE(BatchSimulator<double>::create({nerov, nerov}, {noisy_run(1), noisy_run(2)}, batch, 0, 1));
  const TrackingTask<double> t = task();
  const std::vector<double> a = actions(2);
  Outcome o(2);
  for (int step = 0; step < 3; ++step) {
    tracking_step_batch(t, batch, a.data(), nullptr, o.statuses.data(), o.lanes, o.observation.data(), o.scores);
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_EQ(o.statuses[i], static_cast<std::uint8_t>(Status::ok)) << step;
      EXPECT_EQ(batch.lane(i).steps(), step + 1) << step;
    }
  }
}

}  // namespace
