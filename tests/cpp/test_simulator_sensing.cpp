// The sensors and the estimator in the Simulator, and the water's density:
// what the controller is given (eta_estimate, nu_estimate) against the
// sensors' sampling and latency, each sensor on its own random stream, the
// ideal default, and the named errors.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "neurov/neurov.hpp"
#include "held_command.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using namespace neurov_test;

NEUROV_SCALAR_SUITE(SimulatorSensingTest);

/// A slow drift in x and y, the plant pushed by a constant force.
template <typename S>
SimulationConfig<S> drift() {
  SimulationConfig<S> c;
  c.duration = S(12);
  c.command = held<S>(Vector6<S>::Zero());
  c.eta0 << S(1), S(-2), S(3), S(0), S(0), S(0.3);
  return c;
}

template <typename S>
SimulationResult<S> push(const SimulationConfig<S>& c) {
  Simulator<S> sim;
  EXPECT_TRUE(Simulator<S>::create(Vehicle<S>(nerov_parameters<S>()), c, sim).ok());
  Vector6<S> tau;
  tau << S(60), S(-40), S(0), S(0), S(0), S(5);
  while (!sim.done()) EXPECT_EQ(sim.step(tau, ControllerReport<S>{}), Status::ok);
  return sim.result();
}

TYPED_TEST(SimulatorSensingTest, WithoutSensorsTheControllerIsGivenTheTrueState) {
  using S = TypeParam;
  const SimulationResult<S> r = push(drift<S>());
  EXPECT_EQ(r.eta_estimate, r.eta);
  EXPECT_EQ(r.nu_estimate, r.nu);
}

// A noiseless USBL at 1 Hz with latency L hands on, at row k, the true
// position of the last sample delivered by t_k: the one taken at the last
// whole second s with s + L <= t_k (the initial position before the first).
// What it does not measure (attitude, velocity) is the true state.
TYPED_TEST(SimulatorSensingTest, RawReadingsAreHeldFromTheirSampleTimeAfterTheLatency) {
  using S = TypeParam;
  for (double latency : {0.0, 0.4, 1.5}) {
    SimulationConfig<S> c = drift<S>();
    UsblConfig<S> usbl;
    usbl.rate = 1.0;
    usbl.latency = latency;
    c.sensors.usbl = usbl;
    const SimulationResult<S> r = push(c);
    for (Eigen::Index k = 0; k < r.steps; ++k) {
      const double t = 0.2 * static_cast<double>(k);
      const double sample = std::floor(t - latency + 1e-9);
      const Eigen::Index row = static_cast<Eigen::Index>(std::llround(5 * sample));
      const std::string what = "latency " + std::to_string(latency) + ", k = " + std::to_string(k);
      for (int i = 0; i < 3; ++i) {
        const S expected = sample >= 0 ? r.eta(row, i) : c.eta0(i);
        EXPECT_EQ(r.eta_estimate(k, i), expected) << what;
      }
      EXPECT_EQ(r.eta_estimate.row(k).template tail<3>(), r.eta.row(k).template tail<3>()) << what;
      EXPECT_EQ(r.nu_estimate.row(k), r.nu.row(k)) << what;
    }
  }
}

// Each sensor draws from its own stream: adding the DVL leaves the USBL's
// noise (and so the position handed on) as it was.
TYPED_TEST(SimulatorSensingTest, TurningASensorOnDoesNotReshuffleTheOthers) {
  using S = TypeParam;
  SimulationConfig<S> c = drift<S>();
  c.seed = 11;
  UsblConfig<S> usbl;
  usbl.noise = S(0.5);
  c.sensors.usbl = usbl;
  const SimulationResult<S> alone = push(c);
  DvlConfig<S> dvl;
  dvl.noise = S(0.01);
  c.sensors.dvl = dvl;
  const SimulationResult<S> both = push(c);
  EXPECT_EQ(alone.eta_estimate, both.eta_estimate);
  EXPECT_NE(alone.nu_estimate, both.nu_estimate);
  EXPECT_NE(alone.eta_estimate, alone.eta);
  c.seed = 12;
  EXPECT_NE(push(c).eta_estimate, both.eta_estimate);
}

TYPED_TEST(SimulatorSensingTest, BadSensorsAndAnEstimatorWithoutItsSensorsAreNamedErrors) {
  using S = TypeParam;
  auto field = [](const SimulationConfig<S>& c) {
    const ValidationError e = validate(c);
    return std::string(e.ok() ? "ok" : e.field);
  };
  SimulationConfig<S> c = drift<S>();
  c.estimator.type = EstimatorType::ekf;
  EXPECT_EQ(field(c), "sensors.imu");
  c.sensors.imu = ImuConfig<S>();
  EXPECT_EQ(field(c), "sensors.usbl");
  c.sensors.usbl = UsblConfig<S>();
  EXPECT_EQ(field(c), "ok");
  c.sensors.usbl->rate = -1.0;
  EXPECT_EQ(field(c), "sensors.usbl.rate");
  c.sensors.usbl->rate = 1.0;
  c.sensors.usbl->latency = -0.5;
  EXPECT_EQ(field(c), "sensors.usbl.latency");
  c.sensors.usbl->latency = 0.0;
  c.sensors.dvl = DvlConfig<S>();
  c.sensors.dvl->noise = S(-0.01);
  EXPECT_EQ(field(c), "sensors.dvl.noise");
  c.sensors.dvl->noise = S(0.01);
  c.estimator.linear_acceleration_noise = S(-1);
  EXPECT_EQ(field(c), "estimator.linear_acceleration_noise");
  c.estimator.linear_acceleration_noise = S(0.05);
  c.noise_eta(0) = S(0.1);
  EXPECT_EQ(field(c), "noise_eta");
}

TYPED_TEST(SimulatorSensingTest, BuoyancyIsRhoGVAndTheDensityIsValidated) {
  using S = TypeParam;
  EXPECT_EQ(SimulationConfig<S>().water_density, S(1025));
  for (double rho : {1000.0, 1025.0}) {
    S b = S(0);
    ASSERT_TRUE(buoyancy_in_water(S(rho), S(0.0134), b).ok());
    EXPECT_NEAR(static_cast<double>(b), rho * 9.81 * 0.0134, 1e-12 * rho * 0.0134 * 9.81 +
                                                                  (sizeof(S) == 4 ? 1e-4 : 0.0));
  }
  S b = S(7);
  EXPECT_STREQ(buoyancy_in_water(S(0), S(0.0134), b).field, "water_density");
  EXPECT_STREQ(buoyancy_in_water(S(1025), S(-1), b).field, "displaced_volume");
  EXPECT_EQ(b, S(7));
  SimulationConfig<S> c = drift<S>();
  c.water_density = S(-1);
  EXPECT_STREQ(validate(c).field, "water_density");
}

}  // namespace
