// The Simulator: the plant side of a run as a steppable object, and the
// closed loop built on it.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "legacy_loop.hpp"
#include "neurov/neurov.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::Rng;

template <typename S>
class SimulatorTest : public ::testing::Test {};
TYPED_TEST_SUITE(SimulatorTest, neurov_test::Scalars, neurov_test::ScalarName);

/// A square in the horizontal plane with a turn in yaw, 40 s.
template <typename S>
SimulationConfig<S> square() {
  SimulationConfig<S> c;
  c.duration = S(40);
  c.command.times.resize(5);
  c.command.times << S(0), S(10), S(20), S(30), S(40);
  c.command.poses.setZero(5, 6);
  c.command.poses.row(1) << S(4), S(0), S(1), S(0), S(0), S(0.5);
  c.command.poses.row(2) << S(4), S(4), S(1), S(0), S(0), S(1.5);
  c.command.poses.row(3) << S(0), S(4), S(1), S(0), S(0), S(2.5);
  c.command.poses.row(4) << S(0), S(0), S(0), S(0), S(0), S(3);
  return c;
}

template <typename S>
ThrusterConfig<S> six_thrusters() {
  const double pos[6][3] = {{-0.5, 0.3, 0}, {-0.5, -0.3, 0}, {0.4, 0, 0},
                            {0.4, 0, 0},    {-0.4, 0.3, 0},  {-0.4, -0.3, 0}};
  const double dir[6][3] = {{1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  ThrusterConfig<S> c;
  c.matrix.resize(6, 6);
  for (int j = 0; j < 6; ++j) {
    const Eigen::Vector3d r(pos[j][0], pos[j][1], pos[j][2]), d(dir[j][0], dir[j][1], dir[j][2]);
    c.matrix.col(j) << d.cast<S>(), r.cross(d).cast<S>();
  }
  c.max_thrust = ThrusterConfig<S>::Vector::Constant(6, S(60));
  c.min_thrust = -c.max_thrust;
  c.time_constant = S(0.15);
  return c;
}

/// The configurations every comparison runs: each adds what the loop can do.
template <typename S>
std::vector<std::pair<std::string, SimulationConfig<S>>> configurations() {
  std::vector<std::pair<std::string, SimulationConfig<S>>> out;
  out.emplace_back("plain", square<S>());

  SimulationConfig<S> noisy = square<S>();
  noisy.noise_eta.setConstant(S(0.02));
  noisy.noise_nu.setConstant(S(0.01));
  noisy.seed = 7;
  noisy.command.linear = false;
  out.emplace_back("noise, held command", noisy);

  SimulationConfig<S> faults = noisy;
  faults.command.linear = true;
  SensorFault<S> freeze, dropout, burst;
  freeze.kind = SensorFaultKind::freeze;
  freeze.start = S(3);
  freeze.end = S(5);
  freeze.nu = false;
  dropout.kind = SensorFaultKind::dropout;
  dropout.start = S(9);
  dropout.end = S(11.1);
  burst.kind = SensorFaultKind::noise_burst;
  burst.start = S(15);
  burst.end = S(19);
  burst.noise_eta.setConstant(S(0.1));
  burst.noise_nu.setConstant(S(0.05));
  faults.sensor_faults = {freeze, dropout, burst};
  out.emplace_back("sensor faults, refused steps zero", faults);
  faults.refused_step_policy = RefusedStepPolicy::hold;
  out.emplace_back("sensor faults, refused steps held", faults);

  SimulationConfig<S> thr = square<S>();
  thr.use_thrusters = true;
  thr.thrusters = six_thrusters<S>();
  ThrusterFailure<S> f1, f2;
  f1.index = 2;
  f1.efficiency = S(0.3);
  f1.time = S(7.05);
  f2.index = 4;
  f2.efficiency = S(0);
  f2.time = S(20);
  thr.failures = {f1, f2};
  thr.noise_eta.setConstant(S(0.01));
  thr.seed = 3;
  out.emplace_back("thrusters with failures", thr);
  thr.thrusters.saturation = Saturation::clip;
  out.emplace_back("thrusters with failures, clipped", thr);

  SimulationConfig<S> sea = square<S>();
  sea.current << S(0.2), S(-0.1), S(0);
  sea.current_amplitude << S(0.05), S(0.05), S(0.02);
  sea.current_period = S(12);
  CurrentStep<S> c1, c2;
  c1.time = S(10);
  c1.velocity << S(-0.3), S(0.1), S(0);
  c2.time = S(25.5);
  c2.velocity << S(0), S(0.3), S(0.05);
  sea.current_steps = {c1, c2};
  SinusoidalDisturbance<S> d1, d2;
  d1.dof = 5;
  d1.amplitude = S(20);
  d1.frequency = S(0.1);
  d1.start = S(5);
  d2.dof = 1;
  d2.amplitude = S(15);
  d2.frequency = S(0.05);
  d2.phase = S(0.4);
  sea.disturbances = {d1, d2};
  sea.substeps = 4;
  sea.eta0 << S(0.5), S(-0.5), S(0.2), S(0.05), S(-0.05), S(0.3);
  sea.nu0 << S(0.1), S(0), S(0), S(0), S(0), S(0.02);
  out.emplace_back("current steps and disturbances", sea);

  // A disturbance far beyond what the vehicle can take: the plant diverges.
  SimulationConfig<S> wild = square<S>();
  SinusoidalDisturbance<S> huge;
  huge.dof = 0;
  huge.amplitude = std::numeric_limits<S>::max() / S(8);
  huge.frequency = S(0);
  huge.phase = S(1.5);
  huge.start = S(4);
  wild.disturbances = {huge};
  out.emplace_back("divergence", wild);
  return out;
}

template <typename S>
PDController<S> make_pd() {
  PDConfig<S> cfg;
  cfg.kp << S(200), S(200), S(200), S(50), S(50), S(100);
  cfg.kd << S(300), S(300), S(300), S(60), S(60), S(120);
  return PDController<S>(cfg);
}

template <typename S>
LinearAdaptiveController<S> make_linear() {
  LinearAdaptiveConfig<S> cfg;
  cfg.lambda.setConstant(S(0.5));
  cfg.kd << S(200), S(200), S(200), S(50), S(50), S(100);
  cfg.gamma.setConstant(S(0.5));
  ParameterVector<S> theta;
  EXPECT_TRUE(regressor_parameters(nerov_parameters<S>(), theta).ok());
  cfg.theta0 = theta * S(0.5);
  return LinearAdaptiveController<S>(cfg);
}

template <typename S>
PIDController<S> make_pid() {
  PIDConfig<S> cfg;
  cfg.kp << S(200), S(200), S(200), S(50), S(50), S(100);
  cfg.ki.setConstant(S(5));
  cfg.kd << S(300), S(300), S(300), S(60), S(60), S(120);
  return PIDController<S>(cfg);
}

template <typename S>
SlidingModeController<S> make_smc() {
  SlidingModeConfig<S> cfg;
  cfg.kd << S(200), S(200), S(200), S(50), S(50), S(100);
  cfg.k.setConstant(S(10));
  EXPECT_TRUE(regressor_parameters(nerov_parameters<S>(), cfg.theta).ok());
  return SlidingModeController<S>(cfg);
}

template <typename S>
NNAdaptiveController<S> make_nn() {
  using Ctl = NNAdaptiveController<S>;
  constexpr int n = 20;
  Rng rng(11);
  typename Ctl::Network::CentreMatrix centres(n, kNNInputs);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < centres.cols(); ++i) centres(j, i) = rng.uniform<S>(-2, 2);
  typename Ctl::Network net;
  EXPECT_TRUE(Ctl::Network::create(centres, Ctl::BasisVector::Constant(n, S(2)), net).ok());
  NNAdaptiveConfig<S> cfg;
  cfg.lambda.setConstant(S(0.8));
  cfg.kd << S(200), S(200), S(200), S(50), S(50), S(100);
  cfg.gamma = S(0.5);
  cfg.dt = S(0.2);
  Ctl c;
  EXPECT_TRUE(Ctl::create(net, cfg, c).ok());
  return c;
}

/// Bitwise equality of two arrays (NaN equals NaN of the same bits).
template <typename A, typename B>
::testing::AssertionResult same_bits(const char* what, const A& a, const B& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    return ::testing::AssertionFailure() << what << ": shape " << a.rows() << "x" << a.cols()
                                         << " vs " << b.rows() << "x" << b.cols();
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      const auto x = a(i, j), y = b(i, j);
      if (std::memcmp(&x, &y, sizeof x) != 0)
        return ::testing::AssertionFailure()
               << what << "(" << i << ", " << j << "): " << +x << " vs " << +y;
    }
  return ::testing::AssertionSuccess();
}

template <typename S>
void expect_same_run(const SimulationResult<S>& a, const SimulationResult<S>& b,
                     const std::string& what) {
  EXPECT_EQ(a.steps, b.steps) << what;
  EXPECT_EQ(a.diverged, b.diverged) << what;
  EXPECT_TRUE(same_bits("t", a.t, b.t)) << what;
  EXPECT_TRUE(same_bits("eta", a.eta, b.eta)) << what;
  EXPECT_TRUE(same_bits("nu", a.nu, b.nu)) << what;
  EXPECT_TRUE(same_bits("eta_d", a.eta_d, b.eta_d)) << what;
  EXPECT_TRUE(same_bits("eta_d_dot", a.eta_d_dot, b.eta_d_dot)) << what;
  EXPECT_TRUE(same_bits("tau_demanded", a.tau_demanded, b.tau_demanded)) << what;
  EXPECT_TRUE(same_bits("tau_applied", a.tau_applied, b.tau_applied)) << what;
  EXPECT_TRUE(same_bits("disturbance", a.disturbance, b.disturbance)) << what;
  EXPECT_TRUE(same_bits("s", a.s, b.s)) << what;
  EXPECT_TRUE(same_bits("thrusts", a.thrusts, b.thrusts)) << what;
  EXPECT_TRUE(same_bits("theta", a.theta, b.theta)) << what;
  EXPECT_TRUE(same_bits("adaptive_norm", a.adaptive_norm, b.adaptive_norm)) << what;
  EXPECT_TRUE(same_bits("controller_status", a.controller_status, b.controller_status)) << what;
  EXPECT_TRUE(same_bits("plant_status", a.plant_status, b.plant_status)) << what;
  EXPECT_TRUE(same_bits("faults", a.faults, b.faults)) << what;
}

/// Runs one controller type through both loops on every configuration.
template <typename S, typename Make>
void compare_with_legacy(Make make, const char* name) {
  const Vehicle<S> vehicle(nerov_parameters<S>());
  for (const auto& [label, cfg] : configurations<S>()) {
    const std::string what = std::string(name) + ", " + label;
    auto c_old = make();
    auto c_new = make();
    SimulationResult<S> old_run, new_run;
    ASSERT_TRUE(legacy::simulate_legacy(vehicle, c_old, cfg, old_run).ok()) << what;
    ASSERT_TRUE(simulate(vehicle, c_new, cfg, new_run).ok()) << what;
    expect_same_run(old_run, new_run, what);
  }
}

TYPED_TEST(SimulatorTest, ClosedLoopGivesTheRunsOfThePreviousLoopToTheBit) {
  using S = TypeParam;
  compare_with_legacy<S>(make_pd<S>, "pd");
  compare_with_legacy<S>(make_pid<S>, "pid");
  compare_with_legacy<S>(make_smc<S>, "smc");
  compare_with_legacy<S>(make_linear<S>, "linear");
  compare_with_legacy<S>(make_nn<S>, "nn");
}

// The configurations above exercise what they claim to: otherwise the
// comparison would prove little.
TYPED_TEST(SimulatorTest, ComparisonConfigurationsReachTheirFeatures) {
  using S = TypeParam;
  const Vehicle<S> vehicle(nerov_parameters<S>());
  for (const auto& [label, cfg] : configurations<S>()) {
    auto c = make_pd<S>();
    SimulationResult<S> r;
    ASSERT_TRUE(simulate(vehicle, c, cfg, r).ok()) << label;
    std::uint8_t bits = 0;
    for (Eigen::Index k = 0; k < r.steps; ++k) bits |= r.faults(k);
    if (!cfg.sensor_faults.empty()) {
      EXPECT_EQ(bits & (fault_bits::freeze | fault_bits::dropout | fault_bits::noise_burst),
                fault_bits::freeze | fault_bits::dropout | fault_bits::noise_burst)
          << label;
      EXPECT_GT((r.controller_status.array() != 0).count(), 5) << label;
    }
    if (!cfg.failures.empty()) {
      EXPECT_TRUE(bits & fault_bits::thruster) << label;
    }
    EXPECT_EQ(r.diverged, label == std::string("divergence")) << label;
    if (r.diverged) {
      EXPECT_LT(r.steps, 40) << label;
    }
  }
}

}  // namespace
