// The reference trajectory a batch's lanes share (sim/reference_trajectory.hpp):
// its rows are a reference model's steps to the bit, pitch limit included;
// lanes with the same reference follow one, lanes with another do not, a
// replaced lane joins it, and a lane that follows one gives its run alone.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "neurov/neurov.hpp"
#include "neurov/sim/batch.hpp"
#include "neurov/sim/reference_trajectory.hpp"
#include "controller_state.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using namespace neurov_test;

/// A pose ramp whose pitch is commanded past the reference's pitch limit,
/// so that the limit acts (and sets the pitch_limited fault) mid-run.
SimulationConfig<double> climbing(std::uint64_t seed) {
  SimulationConfig<double> c;
  c.duration = 30.0;
  c.command.times.resize(3);
  c.command.times << 0, 5, 30;
  c.command.poses.setZero(3, 6);
  c.command.poses.row(1) << 1, 0, 0.5, 0, 0.3, 0.2;
  c.command.poses.row(2) << 2, 1, 1.0, 0, 1.6, 0.4;  // 1.6 rad > the 1.37 rad limit
  c.omega.setConstant(0.5);
  c.noise_eta.setConstant(0.01);
  c.seed = seed;
  return c;
}

Eigen::Index rows_of(const SimulationConfig<double>& c) {
  return static_cast<Eigen::Index>(std::llround(c.duration / c.dt)) + 1;
}

TEST(ReferenceTrajectory, ItsRowsAreTheReferenceModelsStepsToTheBit) {
  const SimulationConfig<double> c = climbing(1);
  const Eigen::Index rows = rows_of(c);
  const auto t = ReferenceTrajectory<double>::build(c, rows);
  ASSERT_NE(t, nullptr);
  ReferenceModel<double> model(c.lambda_d, c.omega, c.eta0);
  DesiredState<double> d = model.desired();
  bool limited = false;
  for (Eigen::Index k = 0; k <= rows; ++k) {
    if (k > 0) model.step(c.command.at(static_cast<double>(k - 1) * c.dt), c.dt, d);
    ASSERT_TRUE(t->desired(k).eta_d == d.eta_d) << k;
    ASSERT_TRUE(t->desired(k).eta_d_dot == d.eta_d_dot) << k;
    ASSERT_TRUE(t->desired(k).eta_d_ddot == d.eta_d_ddot) << k;
    ASSERT_EQ(t->pitch_limited(k), model.pitch_limited()) << k;
    limited = limited || model.pitch_limited();
  }
  EXPECT_TRUE(limited) << "the command should reach the pitch limit";
  EXPECT_TRUE(t->matches(c, rows));
  EXPECT_FALSE(t->matches(c, rows + 1));
}

TEST(ReferenceTrajectory, AnyFieldOfTheReferenceMakesAnother) {
  const SimulationConfig<double> c = climbing(1);
  const Eigen::Index rows = rows_of(c);
  const auto t = ReferenceTrajectory<double>::build(c, rows);
  SimulationConfig<double> other = climbing(2);  // another seed: the same reference
  other.current << 0.3, 0, 0;
  EXPECT_TRUE(t->matches(other, rows));
  const auto differs = [&](auto change) {
    SimulationConfig<double> d = c;
    change(d);
    return !t->matches(d, rows_of(d));
  };
  EXPECT_TRUE(differs([](auto& d) { d.eta0(5) = 0.1; }));
  EXPECT_TRUE(differs([](auto& d) { d.lambda_d(0) = 1.5; }));
  EXPECT_TRUE(differs([](auto& d) { d.omega(3) = 0.3; }));
  EXPECT_TRUE(differs([](auto& d) { d.dt = 0.1; }));
  EXPECT_TRUE(differs([](auto& d) { d.command.linear = false; }));
  EXPECT_TRUE(differs([](auto& d) { d.command.poses(2, 0) = 2.5; }));
  EXPECT_TRUE(differs([](auto& d) { d.command.times(1) = 6.0; }));
  EXPECT_TRUE(differs([](auto& d) {
    d.command.times.conservativeResize(4);
    d.command.times(3) = 40.0;
    d.command.poses.conservativeResize(4, 6);
    d.command.poses.row(3).setZero();
  }));
  EXPECT_EQ(ReferenceTrajectory<double>::build(c, ReferenceTrajectory<double>::kMaxRows + 1), nullptr);
}

TEST(ReferenceTrajectory, LanesOfOneReferenceShareItAndGiveTheirRunAlone) {
  const Vehicle<double> nerov(nerov_parameters<double>());
  std::vector<SimulationConfig<double>> configs;
  for (int i = 0; i < 5; ++i) configs.push_back(climbing(static_cast<std::uint64_t>(i)));
  configs[2].eta0(2) = 3.0;  // alone in its reference
  configs[4].use_thrusters = true;
  configs[4].thrusters = nerov_thrusters<double>(60.0);
  std::vector<Vehicle<double>> vehicles(configs.size(), nerov);
  BatchSimulator<double> b;
  ASSERT_TRUE(BatchSimulator<double>::create(vehicles, configs, b).ok());
  for (std::size_t i = 0; i < configs.size(); ++i) EXPECT_EQ(b.shares_reference(i), i != 2) << i;

  std::vector<Simulator<double>> alone(configs.size());
  for (std::size_t i = 0; i < configs.size(); ++i)
    ASSERT_TRUE(Simulator<double>::create(vehicles[i], configs[i], alone[i]).ok());
  std::vector<double> tau(6 * configs.size(), 0.0);
  std::vector<std::uint8_t> statuses(configs.size());
  bool limited = false;
  while (!b.lane(0).done()) {
    for (std::size_t i = 0; i < configs.size(); ++i) {
      // A PD pull towards the desired pose: the runs move, and the rows differ.
      const Observation<double>& o = b.lane(i).observation();
      for (int d = 0; d < 6; ++d) tau[6 * i + d] = 200.0 * (o.desired.eta_d(d) - o.eta(d)) - 100.0 * o.nu(d);
    }
    b.step(tau.data(), nullptr, statuses.data());
    for (std::size_t i = 0; i < configs.size(); ++i) {
      const Status s = alone[i].step(Eigen::Map<const Vector6<double>>(&tau[6 * i]), ControllerReport<double>{});
      ASSERT_EQ(statuses[i], static_cast<std::uint8_t>(s)) << i;
    }
  }
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const SimulationResult<double>& r = b.lane(i).result();
    const SimulationResult<double>& a = alone[i].result();
    ASSERT_EQ(r.steps, a.steps);
    EXPECT_TRUE(r.eta_d == a.eta_d) << i;
    EXPECT_TRUE(r.eta_d_dot == a.eta_d_dot) << i;
    EXPECT_TRUE(r.eta == a.eta) << i;
    EXPECT_TRUE(r.faults == a.faults) << i;
    for (Eigen::Index k = 0; k < r.steps; ++k) limited = limited || (r.faults(k) & fault_bits::pitch_limited);
    EXPECT_TRUE(b.lane(i).observation().desired.eta_d == alone[i].observation().desired.eta_d) << i;
  }
  EXPECT_TRUE(limited);

  // A replaced lane of the shared reference joins it; one of another does not.
  ASSERT_TRUE(b.replace(2, nerov, climbing(9)).ok());
  EXPECT_TRUE(b.shares_reference(2));
  SimulationConfig<double> elsewhere = climbing(9);
  elsewhere.eta0(0) = -1.0;
  ASSERT_TRUE(b.replace(3, nerov, elsewhere).ok());
  EXPECT_FALSE(b.shares_reference(3));
}

TEST(ReferenceTrajectory, ARunLongerThanTheLongestTrajectoryKeepsItsOwn) {
  SimulationConfig<double> c = climbing(1);
  c.duration = 0.2 * static_cast<double>(ReferenceTrajectory<double>::kMaxRows);
  const Vehicle<double> nerov(nerov_parameters<double>());
  BatchSimulator<double> b;
  ASSERT_TRUE(BatchSimulator<double>::create({nerov, nerov}, {c, c}, b, 0, 64).ok());
  EXPECT_FALSE(b.shares_reference(0));
  EXPECT_FALSE(b.shares_reference(1));
}

}  // namespace
