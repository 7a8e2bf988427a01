// The sea in the closed loop: the Gauss-Markov current, the waves and the
// payload events as the Simulator applies them (long seeded runs).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "neurov/neurov.hpp"
#include "held_command.hpp"

namespace {

using namespace neurov;

std::string g3(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

/// A run that holds still: the command is the initial pose.
SimulationConfig<double> still(double duration, double dt, int substeps, double depth) {
  SimulationConfig<double> c;
  c.dt = dt;
  c.substeps = substeps;
  c.duration = duration;
  c.eta0 << 0, 0, depth, 0, 0, 0;
  c.command = neurov_test::held(c.eta0);
  return c;
}

/// NEROV made neutrally buoyant with rho V = B / g = m and r_b = r_g = 0:
/// the body the water carries.
VehicleParameters<double> neutral_nerov() {
  VehicleParameters<double> p = nerov_parameters<double>();
  p.weight = p.buoyancy = p.mass * standard_gravity;
  p.centre_of_buoyancy.setZero();
  return p;
}

SimulationResult<double> run_uncontrolled(const Vehicle<double>& v, const SimulationConfig<double>& c) {
  Simulator<double> sim;
  EXPECT_TRUE(Simulator<double>::create(v, c, sim).ok());
  while (!sim.done()) sim.step(Vector6<double>::Zero(), ControllerReport<double>{});
  SimulationResult<double> r;
  sim.release_result(r);
  return r;
}

TEST(SeaSimulator, NeutrallyBuoyantVehicleMovesWithTheOrbitalFlow) {
  WaveConfig<double> w;  // JONSWAP Hs 2 m, Tp 8 s, 200 components
  SimulationConfig<double> c = still(600.0, 0.2, 10, 10.0);
  c.waves = w;
  c.seed = 7;
  Waves<double> sea;
  ASSERT_TRUE(Waves<double>::create(w, c.seed, sea).ok());
  WaveKinematics<double> k0;
  ASSERT_EQ(sea.evaluate(0.0, c.eta0.head<3>(), k0), Status::ok);
  c.nu0.head<3>() = k0.velocity;  // starts moving with the water
  const SimulationResult<double> r = run_uncontrolled(Vehicle<double>(neutral_nerov()), c);
  ASSERT_FALSE(r.diverged);
  double flow = 0, relative = 0, angle = 0;
  for (Eigen::Index k = 0; k < r.t.size(); ++k) {
    flow = std::max(flow, r.wave_velocity.row(k).norm());
    // The body stays level (irrotational waves), so body and NED axes agree.
    relative = std::max(relative, (r.nu.row(k).head<3>() - r.wave_velocity.row(k)).norm());
    angle = std::max(angle, r.eta.row(k).tail<3>().cwiseAbs().maxCoeff());
  }
  RecordProperty("max_relative_velocity", g3(relative));
  RecordProperty("max_orbital_velocity", g3(flow));
  RecordProperty("max_angle", g3(angle));
  EXPECT_GT(flow, 0.3);
  EXPECT_LT(relative, 1e-5 * flow);
  EXPECT_LT(angle, 1e-6);
  EXPECT_EQ(r.faults.maxCoeff(), 0);  // 10 m is below 1.2 Hs
}

TEST(SeaSimulator, WavesInterpolatedThroughTheSubstepsConvergeWithTheStep) {
  // The waves are followed once per control period and interpolated
  // through the substeps and stages: 10 against 100 substeps of a 0.2 s
  // period (the error against the direct sum at every stage is in
  // test_sea_wave_error.cpp).
  VehicleParameters<double> p = nerov_parameters<double>();
  SimulationConfig<double> c = still(300.0, 0.2, 10, 6.0);
  c.waves = WaveConfig<double>{};
  const SimulationResult<double> a = run_uncontrolled(Vehicle<double>(p), c);
  c.substeps = 100;
  const SimulationResult<double> b = run_uncontrolled(Vehicle<double>(p), c);
  const double diff = (a.nu - b.nu).cwiseAbs().maxCoeff(), scale = b.nu.cwiseAbs().maxCoeff();
  RecordProperty("nu_difference_10_vs_100_substeps", g3(diff / scale));
  EXPECT_LT(diff, 1e-4 * scale);
}

TEST(SeaSimulator, ShallowerThanTheWaveModelIsFlagged) {
  SimulationConfig<double> c = still(20.0, 0.2, 10, 1.0);  // above 1.2 Hs = 2.4 m
  c.waves = WaveConfig<double>{};
  const SimulationResult<double> r = run_uncontrolled(Vehicle<double>(neutral_nerov()), c);
  EXPECT_NE(r.faults(0) & fault_bits::shallow, 0);
}

TEST(SeaSimulator, PayloadPickUpSinksTheVehicleWithTheNewMassMatrix) {
  VehicleParameters<double> p = neutral_nerov();
  p.linear_damping(2) = p.quadratic_damping(2) = 0;  // the sink alone, exactly
  SimulationConfig<double> c = still(1.0, 0.01, 2, 10.0);
  PayloadEvent<double> e;
  e.mass = 10.0;
  c.payload = {e};
  Simulator<double> sim;
  const Vehicle<double> v(p);
  ASSERT_TRUE(Simulator<double>::create(v, c, sim).ok());
  while (!sim.done()) sim.step(Vector6<double>::Zero(), ControllerReport<double>{});
  const double a = 10.0 * standard_gravity / (p.mass + 10.0 + p.added_mass(2, 2));
  EXPECT_NEAR(sim.vehicle().mass_matrix()(2, 2), p.mass + 10.0 + p.added_mass(2, 2), 1e-12);
  const SimulationResult<double> r = sim.result();
  for (Eigen::Index k = 1; k < r.t.size(); ++k) {
    EXPECT_NEAR(r.nu(k, 2), a * r.t(k), 1e-9 * a * r.t(k)) << k;
    EXPECT_EQ(r.payload_mass(k), 10.0);
  }
  // reset() puts the vehicle back as it was at t = 0.
  sim.reset();
  EXPECT_EQ(sim.vehicle().parameters().mass, p.mass);
}

TEST(SeaSimulator, IntegralControllerSettlesWithTheAddedWeight) {
  const VehicleParameters<double> p = nerov_parameters<double>();
  SimulationConfig<double> c = still(200.0, 0.1, 10, 10.0);
  PayloadEvent<double> e;
  e.time = 50.0;
  e.mass = 10.0;
  c.payload = {e};
  PIDConfig<double> pid;
  pid.kp.setConstant(400);
  pid.kd.setConstant(400);
  pid.ki.setConstant(100);
  pid.integral_limit.setConstant(500);
  pid.dt = c.dt;
  PIDController<double> ctrl;
  ASSERT_TRUE(PIDController<double>::create(pid, ctrl).ok());
  SimulationResult<double> r;
  ASSERT_TRUE(simulate(Vehicle<double>(p), ctrl, c, r).ok());
  ASSERT_FALSE(r.diverged);
  const Eigen::Index before = 499, after = r.t.size() - 1;  // t = 49.9 s and 200 s
  // Heave force (body z down) settles lighter by the added weight.
  EXPECT_NEAR(r.tau_demanded(after, 2) - r.tau_demanded(before, 2), -10.0 * standard_gravity,
              1e-3 * 10.0 * standard_gravity);
  EXPECT_NEAR(r.eta(after, 2), 10.0, 1e-4);
  EXPECT_EQ(r.payload_mass(before), 0.0);
  EXPECT_EQ(r.payload_mass(after), 10.0);
}

struct Stats {
  double mean, std, rho_T;
};

Stats speed_stats(double dt, int substeps, double duration, double T) {
  SimulationConfig<double> c = still(duration, dt, substeps, 10.0);
  c.current_model = CurrentModel::gauss_markov;
  c.gauss_markov_current.time_constant = T;
  c.gauss_markov_current.speed_max = 5.0;  // no clipping: the process itself
  c.seed = 11;
  // A vehicle held by nothing drifts; only the logged current matters here.
  const SimulationResult<double> r = run_uncontrolled(Vehicle<double>(nerov_parameters<double>()), c);
  const Eigen::VectorXd v = r.current.rowwise().norm();
  const double mean = v.mean();
  const Eigen::VectorXd x = v.array() - mean;
  const double var = x.squaredNorm() / x.size();
  const Eigen::Index lag = static_cast<Eigen::Index>(std::llround(T / dt));
  const double cov = x.head(x.size() - lag).dot(x.tail(x.size() - lag)) / (x.size() - lag);
  return {mean, std::sqrt(var), cov / var};
}

TEST(SeaSimulator, GaussMarkovCurrentStatisticsDoNotDependOnTheStep) {
  const double T = 30.0, duration = 60000.0;  // 2000 time constants
  // Spread of the estimators (Bartlett): mean sigma sqrt(2T/D), std sigma
  // sqrt(T/D)/..., the autocorrelation about sqrt(2T/D); bounds 5 times that.
  const double n = duration / T;
  for (const auto& [dt, substeps] : {std::pair{0.5, 1}, std::pair{2.0, 1}, std::pair{2.0, 4}}) {
    const Stats s = speed_stats(dt, substeps, duration, T);
    EXPECT_NEAR(s.mean, 0.5, 5 * 0.1 * std::sqrt(2 / n)) << dt;
    EXPECT_NEAR(s.std, 0.1, 5 * 0.1 * std::sqrt(1 / n)) << dt;
    EXPECT_NEAR(s.rho_T, std::exp(-1.0), 5 * std::sqrt(2 / n)) << dt;
  }
  // Substeps do not change the realisation at all.
  SimulationConfig<double> c = still(600.0, 0.5, 1, 10.0);
  c.current_model = CurrentModel::gauss_markov;
  const Vehicle<double> v(nerov_parameters<double>());
  const SimulationResult<double> a = run_uncontrolled(v, c);
  c.substeps = 7;
  const SimulationResult<double> b = run_uncontrolled(v, c);
  EXPECT_EQ(a.current, b.current);
}

TEST(SeaSimulator, WavesAndCurrentLeaveTheMeasurementNoiseAsItWas) {
  SimulationConfig<double> c = still(100.0, 0.2, 10, 10.0);
  c.noise_eta.setConstant(0.1);
  c.noise_nu.setConstant(0.05);
  c.seed = 3;
  const Vehicle<double> v(nerov_parameters<double>());
  const auto noise = [&](const SimulationConfig<double>& cfg) {
    Simulator<double> sim;
    EXPECT_TRUE(Simulator<double>::create(v, cfg, sim).ok());
    std::vector<double> out;
    while (!sim.done()) {
      for (int i = 0; i < 6; ++i) {
        out.push_back(sim.observation().eta(i) - sim.eta()(i));
        out.push_back(sim.observation().nu(i) - sim.nu()(i));
      }
      sim.step(Vector6<double>::Zero(), ControllerReport<double>{});
    }
    return out;
  };
  const std::vector<double> calm = noise(c);
  c.waves = WaveConfig<double>{};
  c.current_model = CurrentModel::gauss_markov;
  const std::vector<double> sea = noise(c);
  ASSERT_EQ(calm.size(), sea.size());
  for (std::size_t i = 0; i < calm.size(); ++i) EXPECT_NEAR(calm[i], sea[i], 1e-12) << i;
}

TEST(SeaSimulator, BadSeaConfigurationsAreRefusedByName) {
  const Vehicle<double> v(nerov_parameters<double>());
  Simulator<double> sim;
  SimulationConfig<double> c = still(10.0, 0.2, 10, 10.0);
  c.waves = WaveConfig<double>{};
  c.waves->hs = 0;
  EXPECT_STREQ(validate(c).field, "hs");
  c.waves.reset();
  c.current_model = CurrentModel::gauss_markov;
  c.gauss_markov_current.time_constant = 0;
  EXPECT_STREQ(validate(c).field, "time_constant");
  c.gauss_markov_current.time_constant = 30;
  c.current << 0.1, 0, 0;
  EXPECT_STREQ(validate(c).field, "current_model");
  c.current.setZero();
  PayloadEvent<double> e;
  e.time = 5;
  e.mass = -200;  // more than NEROV's 185 kg
  c.payload = {e, e};
  const ValidationError err = Simulator<double>::create(v, c, sim);
  EXPECT_STREQ(err.field, "payload.mass");
  EXPECT_EQ(err.index, 0);
  c.payload[0].mass = 1;
  c.payload[1].time = 4;
  EXPECT_STREQ(validate(c).field, "payload.time");
  EXPECT_EQ(validate(c).index, 1);
}

}  // namespace
