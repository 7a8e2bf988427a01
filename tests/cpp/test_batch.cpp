// The batch (sim/batch.hpp): a lane gives exactly the run alone, for every
// built-in controller, with thrusters, sensors and the EKF, waves, perturbed
// plants in and out of the SIMD kernel and a lane that diverges while the
// others go on; the metric sums are those of the rows.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "neurov/neurov.hpp"
#include "neurov/sim/batch.hpp"
#include "controller_state.hpp"
#include "sensor_suite.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using namespace neurov_test;

/// A short square with noise: every lane differs by its seed.
SimulationConfig<double> lane_config(std::uint64_t seed) {
  SimulationConfig<double> c;
  c.duration = 8.0;
  c.command.times.resize(3);
  c.command.times << 0, 4, 8;
  c.command.poses.setZero(3, 6);
  c.command.poses.row(1) << 2, 0, 1, 0, 0, 0.5;
  c.command.poses.row(2) << 2, 2, 1, 0, 0, 1.0;
  c.noise_eta.setConstant(0.01);
  c.noise_nu.setConstant(0.005);
  c.seed = seed;
  return c;
}

/// The configurations of the lanes: plain, thrusters, sensors with the EKF,
/// waves, and one whose plant diverges (a force of 1e30 N).
std::vector<SimulationConfig<double>> lane_configs() {
  std::vector<SimulationConfig<double>> out;
  out.push_back(lane_config(1));
  SimulationConfig<double> thr = lane_config(2);
  thr.use_thrusters = true;
  thr.thrusters = nerov_thrusters<double>(60.0);
  out.push_back(thr);
  SimulationConfig<double> ekf = lane_config(3);
  ekf.sensors = sensor_suite<double>();  // the sensors' noise, not the measurement noise
  ekf.noise_eta.setZero();
  ekf.noise_nu.setZero();
  ekf.estimator.type = EstimatorType::ekf;
  out.push_back(ekf);
  SimulationConfig<double> sea = lane_config(4);
  sea.eta0(2) = 20.0;
  sea.waves = WaveConfig<double>{};
  out.push_back(sea);
  return out;
}

template <typename Config, typename = void>
struct has_model_theta : std::false_type {};
template <typename Config>
struct has_model_theta<Config, std::void_t<decltype(Config::theta)>> : std::true_type {};
template <typename Config, typename = void>
struct has_model_vehicle : std::false_type {};
template <typename Config>
struct has_model_vehicle<Config, std::void_t<decltype(Config::vehicle)>> : std::true_type {};

/// A controller with its defaults and, where it has one, NEROV as its model.
template <typename Ctl>
Ctl make_controller() {
  typename Ctl::Config c;
  if constexpr (has_model_theta<typename Ctl::Config>::value)
    EXPECT_TRUE(regressor_parameters(nerov_parameters<double>(), c.theta).ok());
  if constexpr (has_model_vehicle<typename Ctl::Config>::value) c.vehicle = nerov_parameters<double>();
  if constexpr (std::is_constructible_v<Ctl, const typename Ctl::Config&>) {
    return Ctl(c);
  } else {  // the NN controller, on 12 centres
    Rng rng(5);
    typename Ctl::Network::CentreMatrix centres(12, kNNInputs);
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < kNNInputs; ++i) centres(j, i) = rng.uniform<double>(-1.5, 1.5);
    typename Ctl::Network net;
    EXPECT_TRUE(Ctl::Network::create(centres, Ctl::BasisVector::Constant(12, 2.0), net).ok());
    return Ctl(net, c);
  }
}

/// Every series equal, bit for bit (NaN where NaN).
void expect_same(const SimulationResult<double>& a, const SimulationResult<double>& b,
                 const std::string& what) {
  ASSERT_EQ(a.diverged, b.diverged) << what;
  ASSERT_EQ(a.t.size(), b.t.size()) << what;
  SimulationResult<double> aa = a, bb = b;
  std::size_t i = 0;
  std::vector<std::pair<Eigen::ArrayXd, std::string>> left;
  aa.visit([&](const SeriesSpec& spec, auto& s) {
    left.emplace_back(Eigen::Map<const Eigen::Matrix<typename std::decay_t<decltype(s)>::Scalar, Eigen::Dynamic, 1>>(
                          s.data(), s.size()).template cast<double>().array(),
                      spec.name);
  });
  bb.visit([&](const SeriesSpec&, auto& s) {
    const Eigen::ArrayXd right =
        Eigen::Map<const Eigen::Matrix<typename std::decay_t<decltype(s)>::Scalar, Eigen::Dynamic, 1>>(
            s.data(), s.size()).template cast<double>().array();
    const Eigen::ArrayXd& l = left[i].first;
    ASSERT_EQ(l.size(), right.size()) << what << " " << left[i].second;
    for (Eigen::Index k = 0; k < l.size(); ++k)
      ASSERT_TRUE(l(k) == right(k) || (std::isnan(l(k)) && std::isnan(right(k))))
          << what << " " << left[i].second << "[" << k << "]: " << l(k) << " vs " << right(k);
    ++i;
  });
}

TEST(Batch, EveryLaneIsTheRunAloneForEveryBuiltInControllerMixed) {
  std::vector<Vehicle<double>> vehicles;
  std::vector<AnyBuiltInController<double>> controllers;
  std::vector<SimulationConfig<double>> configs;
  std::vector<std::string> names;
  const Vehicle<double> nerov(nerov_parameters<double>());
  // Beside NEROV a perturbed plant (in the SIMD kernel) and one with its
  // centre of gravity below the origin (r_g != 0: the scalar step).
  VehicleParameters<double> heavier = nerov_parameters<double>();
  heavier.mass *= 1.2;
  heavier.buoyancy *= 1.2;
  VehicleParameters<double> low_cg = nerov_parameters<double>();
  low_cg.centre_of_gravity << 0.0, 0.0, 0.05;
  const std::vector<Vehicle<double>> plants = {nerov, Vehicle<double>(heavier), Vehicle<double>(low_cg)};
  ASSERT_TRUE(plants[1].diagonal());
  ASSERT_FALSE(plants[2].diagonal());
  for_each_type(BuiltInControllers<double>{}, [&](auto tag) {
    using C = typename decltype(tag)::type;
    const std::vector<SimulationConfig<double>> lanes = lane_configs();
    for (std::size_t l = 0; l < lanes.size() + 2; ++l) {
      vehicles.push_back(l < lanes.size() ? nerov : plants[l - lanes.size() + 1]);
      controllers.emplace_back(std::in_place_type<C>, make_controller<C>());
      configs.push_back(l < lanes.size() ? lanes[l] : lanes[l % 2]);
      names.push_back(std::string(typeid(C).name()) + " lane " + std::to_string(configs.size() - 1));
    }
  });
  const std::vector<AnyBuiltInController<double>> fresh = controllers;
  for (unsigned threads : {1u, 3u}) {
    std::vector<AnyBuiltInController<double>> ctl = fresh;
    BatchOptions options;
    options.threads = threads;
    std::vector<SimulationResult<double>> results;
    std::size_t lane = 0;
    const ValidationError e = run_batch(vehicles, ctl, configs, options, &results, nullptr, &lane);
    ASSERT_TRUE(e.ok()) << "lane " << lane << ": " << e.field;
    ASSERT_EQ(results.size(), vehicles.size());
    for (std::size_t i = 0; i < vehicles.size(); ++i) {
      SimulationResult<double> alone;
      std::visit(
          [&](auto c) { ASSERT_TRUE(simulate(vehicles[i], c, configs[i], alone).ok()); },
          AnyBuiltInController<double>(fresh[i]));
      expect_same(results[i], alone, names[i] + " threads " + std::to_string(threads));
    }
  }
}

TEST(Batch, ADivergingLaneStopsWhileTheOthersGoOn) {
  const Vehicle<double> nerov(nerov_parameters<double>());
  std::vector<Vehicle<double>> vehicles(3, nerov);
  std::vector<SimulationConfig<double>> configs = {lane_config(1), lane_config(2), lane_config(3)};
  BatchSimulator<double> b;
  ASSERT_TRUE(BatchSimulator<double>::create(vehicles, configs, b).ok());
  std::vector<Simulator<double>> alone(3);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(Simulator<double>::create(vehicles[i], configs[i], alone[i]).ok());
  std::vector<double> tau(18, 0.0);
  bool mask[3] = {true, true, false};
  std::uint8_t statuses[3];
  Eigen::Index diverged_at = -1;
  for (int k = 0; k < 200 && !b.lane(0).done(); ++k) {
    for (int i = 0; i < 3; ++i) tau[6 * i] = 10.0 * std::sin(0.1 * k + i);
    tau[6] = k >= 5 ? 1e300 : 0.0;  // lane 1 is pushed until its plant diverges
    mask[2] = k % 2 == 0;           // lane 2 steps every other period
    b.step(tau.data(), mask, statuses);
    for (int i = 0; i < 3; ++i) {
      const bool stepped = mask[i] && !alone[i].done();
      if (!stepped) {
        EXPECT_EQ(statuses[i], kLaneNotStepped);
        continue;
      }
      const Status s = alone[i].step(Eigen::Map<const Vector6<double>>(&tau[6 * i]), ControllerReport<double>{});
      EXPECT_EQ(statuses[i], static_cast<std::uint8_t>(s)) << "lane " << i << " step " << k;
    }
    if (b.lane(1).diverged() && diverged_at < 0) diverged_at = b.lane(1).steps();
  }
  EXPECT_GT(diverged_at, 0);
  EXPECT_TRUE(b.lane(0).done());
  EXPECT_FALSE(b.lane(0).diverged());
  for (int i = 0; i < 3; ++i) expect_same(b.lane(i).result(), alone[i].result(), "lane " + std::to_string(i));
}

TEST(Batch, APayloadPickedUpBetweenTwoSubstepsMovesOnlyItsLane) {
  // Held at the centre of gravity the plant stays in the SIMD kernel, whose
  // block keeps each lane's coefficients from substep to substep: every
  // other lane's event, inside a control period, must reach its lane alone.
  const Vehicle<double> nerov(nerov_parameters<double>());
  std::vector<Vehicle<double>> vehicles(20, nerov);
  std::vector<SimulationConfig<double>> configs;
  for (int i = 0; i < 20; ++i) {
    SimulationConfig<double> c = lane_config(static_cast<std::uint64_t>(i));
    if (i % 2 == 0) {
      PayloadEvent<double> e;
      e.time = 1.03 + 0.1 * (i % 4);  // between substeps 1.02 and 1.04 s (h = 0.02 s)
      e.mass = 20.0 + i;
      c.payload.push_back(e);
    }
    configs.push_back(c);
  }
  ASSERT_TRUE(Vehicle<double>(nerov).diagonal());
  std::vector<AnyBuiltInController<double>> ctl(
      20, AnyBuiltInController<double>(make_controller<PDController<double>>()));
  const std::vector<AnyBuiltInController<double>> fresh = ctl;
  BatchOptions options;
  options.threads = 1;
  std::vector<SimulationResult<double>> results;
  ASSERT_TRUE(run_batch(vehicles, ctl, configs, options, &results, nullptr).ok());
  for (std::size_t i = 0; i < 20; ++i) {
    SimulationResult<double> alone;
    std::visit([&](auto c) { ASSERT_TRUE(simulate(vehicles[i], c, configs[i], alone).ok()); },
               AnyBuiltInController<double>(fresh[i]));
    expect_same(results[i], alone, "lane " + std::to_string(i));
    EXPECT_EQ(results[i].payload_mass(results[i].steps - 1) > 0, i % 2 == 0) << i;
  }
  SimulationResult<double> plain;
  SimulationConfig<double> c0 = configs[0];
  c0.payload.clear();
  std::visit([&](auto c) { ASSERT_TRUE(simulate(vehicles[0], c, c0, plain).ok()); },
             AnyBuiltInController<double>(fresh[0]));
  EXPECT_NE(plain.eta(plain.steps - 1, 2), results[0].eta(results[0].steps - 1, 2));
}

TEST(Batch, MetricSumsAreThoseOfTheRows) {
  const Vehicle<double> nerov(nerov_parameters<double>());
  std::vector<Vehicle<double>> vehicles(2, nerov);
  std::vector<SimulationConfig<double>> configs = {lane_config(1), lane_config(2)};
  configs[1].duration = 20.0;  // more rows than the metrics' window of rows
  std::vector<AnyBuiltInController<double>> ctl(2, AnyBuiltInController<double>(make_controller<PDController<double>>()));
  std::vector<AnyBuiltInController<double>> ctl2 = ctl;
  BatchOptions full, sums_only;
  sums_only.metrics_only = true;
  sums_only.after = {3.0, 3.0};
  std::vector<SimulationResult<double>> results;
  std::vector<RunSums> sums;
  ASSERT_TRUE(run_batch(vehicles, ctl, configs, full, &results, nullptr).ok());
  ASSERT_TRUE(run_batch(vehicles, ctl2, configs, sums_only, static_cast<std::vector<SimulationResult<double>>*>(nullptr), &sums).ok());
  for (int i = 0; i < 2; ++i) {
    RunSums expected;
    expected.after = 3.0;
    expected.add(results[i], results[i].t.size());
    EXPECT_EQ(sums[i].window.rows + sums[i].before.rows, results[i].t.size());
    EXPECT_EQ(sums[i].window.rows, expected.window.rows);
    EXPECT_EQ(sums[i].window.e2, expected.window.e2);
    EXPECT_EQ(sums[i].window.max_abs_tau_dof, expected.window.max_abs_tau_dof);
    EXPECT_EQ(sums[i].before.tau_norm, expected.before.tau_norm);
    EXPECT_EQ(sums[i].window.t_first, 3.0);
    EXPECT_EQ(sums[i].max_adaptive_norm, expected.max_adaptive_norm);
  }
}

TEST(Batch, ARefusedLaneIsNamedAndNothingRuns) {
  const Vehicle<double> nerov(nerov_parameters<double>());
  std::vector<Vehicle<double>> vehicles(3, nerov);
  std::vector<SimulationConfig<double>> configs = {lane_config(1), lane_config(2), lane_config(3)};
  configs[2].dt = -1.0;
  BatchSimulator<double> b;
  std::size_t lane = 99;
  const ValidationError e = BatchSimulator<double>::create(vehicles, configs, b, 0, 0, &lane);
  EXPECT_FALSE(e.ok());
  EXPECT_EQ(lane, 2u);
  EXPECT_EQ(std::string(e.field), "dt");
  EXPECT_EQ(b.size(), 0u);
  configs[2].dt = lane_config(1).dt;
  ASSERT_TRUE(BatchSimulator<double>::create(vehicles, configs, b).ok());
  SimulationConfig<double> bad = lane_config(9);
  bad.substeps = 0;
  EXPECT_FALSE(b.replace(1, nerov, bad).ok());
  EXPECT_EQ(b.lane(1).config().seed, 2u);  // lane 1 untouched
}

TEST(Batch, AReadoutStacksEachLanesStateInItsRow) {
  const Vehicle<double> nerov(nerov_parameters<double>());
  std::vector<Vehicle<double>> vehicles(3, nerov);
  std::vector<SimulationConfig<double>> configs = {lane_config(1), lane_config(2), lane_config(3)};
  BatchSimulator<double> b;
  ASSERT_TRUE(BatchSimulator<double>::create(vehicles, configs, b).ok());
  std::vector<double> tau(18, 5.0);
  std::vector<std::uint8_t> statuses(3);
  const bool mask[3] = {true, false, true};
  b.step(tau.data(), mask, statuses.data());
  std::vector<double> t(3), eta(18), nu_true(18);
  bool done[3];
  std::int64_t steps[3], left[3];
  LaneReadout<double> r;
  r.t = t.data();
  r.eta = eta.data();
  r.nu_true = nu_true.data();
  r.done = done;
  r.steps = steps;
  r.steps_left = left;
  r.read(b);
  for (std::size_t i = 0; i < 3; ++i) {
    const Simulator<double>& s = b.lane(i);
    EXPECT_EQ(t[i], s.observation().t);
    EXPECT_TRUE((Eigen::Map<const Vector6<double>>(eta.data() + 6 * i).array() == s.observation().eta.array()).all());
    EXPECT_TRUE((Eigen::Map<const Vector6<double>>(nu_true.data() + 6 * i).array() == s.nu().array()).all());
    EXPECT_EQ(done[i], s.done());
    EXPECT_EQ(steps[i], mask[i] ? 1 : 0);
    EXPECT_EQ(left[i], s.planned_steps() - steps[i]);
  }
}

}  // namespace
