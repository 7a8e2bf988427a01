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

#include "neurov/neurov.hpp"
#include "controller_state.hpp"
#include "sensor_suite.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using namespace neurov_test;

NEUROV_SCALAR_SUITE(SimulatorTest);

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

/// NEROV's layout, weaker thrusters with a lag.
template <typename S>
ThrusterConfig<S> six_thrusters() {
  ThrusterConfig<S> c = neurov_test::nerov_thrusters<S>(S(60));
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
  SensorFault<S> freeze = sensor_fault<S>(SensorFaultKind::freeze, 3, 5);
  freeze.nu = false;
  SensorFault<S> burst = sensor_fault<S>(SensorFaultKind::noise_burst, 15, 19);
  burst.noise_eta.setConstant(S(0.1));
  burst.noise_nu.setConstant(S(0.05));
  faults.sensor_faults = {freeze, sensor_fault<S>(SensorFaultKind::dropout, 9, 11.1), burst};
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
  thr.thruster_failures = {f1, f2};
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

/// Per-DOF gains of the controllers below: one for surge, sway and heave, one
/// for roll and pitch, one for yaw.
template <typename S>
Vector6<S> gains(double translation, double roll_pitch, double yaw) {
  Vector6<S> g;
  g << S(translation), S(translation), S(translation), S(roll_pitch), S(roll_pitch), S(yaw);
  return g;
}

/// The PD's gains: the PID keeps them and adds an integral.
template <template <typename> class Config, typename S>
Config<S> with_pd_gains() {
  Config<S> cfg;
  cfg.kp = gains<S>(200, 50, 100);
  cfg.kd = gains<S>(300, 60, 120);
  return cfg;
}

template <typename S>
PDController<S> make_pd() {
  return PDController<S>(with_pd_gains<PDConfig, S>());
}

template <typename S>
LinearAdaptiveController<S> make_linear() {
  LinearAdaptiveConfig<S> cfg;
  cfg.lambda.setConstant(S(0.5));
  cfg.kd = gains<S>(200, 50, 100);
  cfg.gamma.setConstant(S(0.5));
  ParameterVector<S> theta;
  EXPECT_TRUE(regressor_parameters(nerov_parameters<S>(), theta).ok());
  cfg.theta0 = theta * S(0.5);
  return LinearAdaptiveController<S>(cfg);
}

template <typename S>
PIDController<S> make_pid() {
  auto cfg = with_pd_gains<PIDConfig, S>();
  cfg.ki.setConstant(S(5));
  return PIDController<S>(cfg);
}

template <typename S>
SlidingModeController<S> make_smc() {
  SlidingModeConfig<S> cfg;
  cfg.kd = gains<S>(200, 50, 100);
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
  cfg.kd = gains<S>(200, 50, 100);
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

/// The closed loop written out by hand on the Simulator's public API.
template <typename S, typename Controller>
void drive(Simulator<S>& sim, Controller& controller) {
  Eigen::Matrix<S, 1, kMaxLoggedParameters> parameters;
  Vector6<S> tau;
  while (!sim.done()) {
    const Observation<S>& o = sim.observation();
    const Status cs = controller.step(o.eta, o.nu, o.desired, tau);
    sim.step(tau, controller_report<S>(controller, cs, parameters));
  }
}

/// For each configuration above, on NEROV: its whole closed-loop run by a
/// controller from make(), then check(label, cfg, vehicle, whole).
template <typename S, typename Make, typename Check>
void for_each_run(Make make, Check check) {
  const Vehicle<S> vehicle(nerov_parameters<S>());
  for (const auto& [label, cfg] : configurations<S>()) {
    auto c = make();
    SimulationResult<S> whole;
    ASSERT_TRUE(simulate(vehicle, c, cfg, whole).ok()) << label;
    check(label, cfg, vehicle, whole);
  }
}

/// simulate() and a run stepped by hand agree, and reset() replays the run.
template <typename S, typename Make>
void expect_stepped_run_is_simulate(Make make, const char* name) {
  SCOPED_TRACE(name);
  for_each_run<S>(make, [&](const std::string& label, const SimulationConfig<S>& cfg,
                            const Vehicle<S>& vehicle, const SimulationResult<S>& whole) {
    const std::string what = std::string(name) + ", " + label;
    auto c2 = make();
    Simulator<S> sim;
    Eigen::Matrix<S, 1, kMaxLoggedParameters> buffer;
    const int logged = controller_report<S>(c2, Status::ok, buffer).parameter_count;
    ASSERT_TRUE(Simulator<S>::create(vehicle, cfg, sim, logged).ok()) << what;
    drive(sim, c2);
    expect_same_run(sim.result(), whole, what);
    sim.reset();
    c2.reset();
    drive(sim, c2);
    expect_same_run(sim.result(), whole, what + ", after reset()");
  });
}

TYPED_TEST(SimulatorTest, ARunSteppedByHandIsTheClosedLoop) {
  using S = TypeParam;
  expect_stepped_run_is_simulate<S>(make_pd<S>, "pd");
  expect_stepped_run_is_simulate<S>(make_linear<S>, "linear");
  expect_stepped_run_is_simulate<S>(make_nn<S>, "nn");
}

/// The rows first .. first + n - 1 of `whole`, for comparing a chunk.
template <typename S>
SimulationResult<S> rows_of(const SimulationResult<S>& whole, Eigen::Index first, Eigen::Index n) {
  SimulationResult<S> out;
  out.t = whole.t.segment(first, n);
  for (auto [to, from] : {std::pair{&out.eta, &whole.eta}, {&out.nu, &whole.nu},
                          {&out.eta_d, &whole.eta_d}, {&out.eta_d_dot, &whole.eta_d_dot},
                          {&out.tau_demanded, &whole.tau_demanded},
                          {&out.tau_applied, &whole.tau_applied},
                          {&out.disturbance, &whole.disturbance}, {&out.s, &whole.s}})
    *to = from->middleRows(first, n);
  out.thrusts = whole.thrusts.middleRows(first, n);
  out.theta = whole.theta.middleRows(first, n);
  out.adaptive_norm = whole.adaptive_norm.segment(first, n);
  out.controller_status = whole.controller_status.segment(first, n);
  out.plant_status = whole.plant_status.segment(first, n);
  out.faults = whole.faults.segment(first, n);
  out.steps = n;
  out.diverged = whole.diverged;
  return out;
}

// A run handed over in chunks is the whole run cut in pieces, bit for bit,
// whatever the chunk size (one row, a prime, the run's length and more);
// only the last chunk says that the run diverged.
TYPED_TEST(SimulatorTest, ChunksTogetherAreTheWholeRun) {
  using S = TypeParam;
  for_each_run<S>(make_linear<S>, [](const std::string& label, const SimulationConfig<S>& cfg,
                                     const Vehicle<S>& vehicle, const SimulationResult<S>& whole) {
    for (const Eigen::Index chunk_rows : {Eigen::Index(1), Eigen::Index(13), whole.steps,
                                          Eigen::Index(1000)}) {
      const std::string what = label + ", chunks of " + std::to_string(chunk_rows);
      auto controller = make_linear<S>();
      Eigen::Index first = 0;
      int chunks = 0;
      ASSERT_TRUE(simulate_in_chunks(vehicle, controller, cfg, chunk_rows,
                                     [&](const SimulationResult<S>& chunk) {
                                       const Eigen::Index n = chunk.t.size();
                                       ASSERT_GE(n, 1) << what;
                                       ASSERT_LE(n, chunk_rows) << what;
                                       ASSERT_LE(first + n, whole.steps) << what;
                                       SimulationResult<S> expected = rows_of(whole, first, n);
                                       expected.diverged = whole.diverged && first + n == whole.steps;
                                       expect_same_run(chunk, expected, what);
                                       first += n;
                                       ++chunks;
                                     })
                      .ok())
          << what;
      EXPECT_EQ(first, whole.steps) << what;
      EXPECT_EQ(chunks, (whole.steps + chunk_rows - 1) / chunk_rows) << what;
    }
    auto controller = make_linear<S>();
    const auto e = simulate_in_chunks(vehicle, controller, cfg, Eigen::Index(0),
                                      [](const SimulationResult<S>&) { FAIL() << "a chunk"; });
    EXPECT_EQ(std::string(e.field), "chunk_rows") << label;
  });
}

// A full log window refuses the step and changes nothing; drain() hands the
// rows over, and the run goes on as if the window were the whole run.
TYPED_TEST(SimulatorTest, AFullLogWindowRefusesUntilDrained) {
  using S = TypeParam;
  const Vehicle<S> vehicle(nerov_parameters<S>());
  const SimulationConfig<S> cfg = square<S>();
  Simulator<S> windowed, whole;
  ASSERT_TRUE(Simulator<S>::create(vehicle, cfg, windowed, 0, 5).ok());
  ASSERT_TRUE(Simulator<S>::create(vehicle, cfg, whole).ok());
  EXPECT_EQ(windowed.log_rows(), 5);
  EXPECT_EQ(whole.log_rows(), whole.planned_steps());
  Simulator<S> refused;
  EXPECT_EQ(std::string(Simulator<S>::create(vehicle, cfg, refused, 0, -1).field), "log_rows");
  Vector6<S> tau;
  tau << S(10), S(-5), S(2), S(0), S(1), S(-1);
  const ControllerReport<S> report;
  for (int k = 0; k < 5; ++k) ASSERT_EQ(windowed.step(tau, report), whole.step(tau, report));
  EXPECT_TRUE(windowed.log_full());
  EXPECT_FALSE(windowed.done());
  const Vector6<S> eta = windowed.eta();
  EXPECT_EQ(windowed.step(tau, report), Status::invalid_argument);
  EXPECT_EQ(windowed.steps(), 5);
  EXPECT_EQ(windowed.eta(), eta);
  SimulationResult<S> first;
  EXPECT_EQ(windowed.drain(first), 5);
  EXPECT_EQ(windowed.logged_from(), 5);
  EXPECT_FALSE(windowed.log_full());
  EXPECT_EQ(windowed.result().t.size(), 0);
  for (int k = 0; k < 3; ++k) ASSERT_EQ(windowed.step(tau, report), whole.step(tau, report));
  const SimulationResult<S> all = whole.result();
  expect_same_run(first, rows_of(all, 0, 5), "first window");
  expect_same_run(windowed.result(), rows_of(all, 5, 3), "second window");
  windowed.reset();
  EXPECT_EQ(windowed.logged_from(), 0);
  EXPECT_EQ(windowed.steps(), 0);
}

// An independent reference for the timing: with no noise, no thrusters and a
// force that depends on t only, row k is rk4_step applied substeps times from
// row k-1 with the force plus the disturbance at each substep, and eta_d is a
// ReferenceModel stepped at dt with the command at t_k.
TYPED_TEST(SimulatorTest, RowsFollowTheZeroOrderHoldAndRk4Substeps) {
  using S = TypeParam;
  const Vehicle<S> vehicle(nerov_parameters<S>());
  SimulationConfig<S> cfg = configurations<S>()[6].second;  // current steps and disturbances
  ASSERT_EQ(configurations<S>()[6].first, "current steps and disturbances");
  cfg.duration = S(12);
  Simulator<S> sim;
  ASSERT_TRUE(Simulator<S>::create(vehicle, cfg, sim).ok());
  auto force = [](S t) {
    Vector6<S> f;
    f << S(40) * std::sin(t), S(-20), S(10) * std::cos(t / S(3)), S(0), S(1), S(-2) * t;
    return f;
  };
  ReferenceModel<S> reference(cfg.lambda_d, cfg.omega, cfg.eta0);
  DesiredState<S> desired = reference.desired();
  Vector6<S> eta = cfg.eta0, nu = cfg.nu0;
  const S h = cfg.dt / S(cfg.substeps);
  const S two_pi = S(6.283185307179586);
  while (!sim.done()) {
    const Eigen::Index k = sim.steps();
    const S t = S(k) * cfg.dt;
    EXPECT_EQ(sim.observation().t, t);
    EXPECT_EQ(sim.observation().eta, eta) << "k = " << k;  // no noise: the true state
    EXPECT_EQ(sim.observation().desired.eta_d, desired.eta_d) << "k = " << k;
    EXPECT_EQ(sim.observation().desired.eta_d_ddot, desired.eta_d_ddot) << "k = " << k;
    ASSERT_EQ(sim.step(force(t), ControllerReport<S>{}), Status::ok);
    for (int j = 0; j < cfg.substeps; ++j) {
      const S ts = t + S(j) * h;
      Vector6<S> d = Vector6<S>::Zero();
      for (const auto& dist : cfg.disturbances)
        if (ts >= dist.start)
          d(dist.dof) +=
              dist.amplitude * std::sin(two_pi * dist.frequency * (ts - dist.start) + dist.phase);
      Vector3<S> current = cfg.current;
      for (const auto& step : cfg.current_steps)
        if (ts >= step.time) current = step.velocity;
      current += cfg.current_amplitude * std::sin(two_pi * ts / cfg.current_period);
      ASSERT_EQ(rk4_step(vehicle, eta, nu, Vector6<S>(force(t) + d), h, current), Status::ok);
    }
    reference.step(cfg.command.at(t), cfg.dt, desired);
    EXPECT_EQ(sim.eta(), eta) << "k = " << k;
    EXPECT_EQ(sim.nu(), nu) << "k = " << k;
  }
  EXPECT_EQ(sim.steps(), 61);
  const SimulationResult<S> r = sim.result();
  EXPECT_EQ(r.steps, 61);
  EXPECT_EQ(r.tau_demanded.row(60).transpose(), force(S(60) * cfg.dt));
  EXPECT_EQ(r.tau_applied.row(60), r.tau_demanded.row(60));
}

TYPED_TEST(SimulatorTest, RejectedCallsChangeNothing) {
  using S = TypeParam;
  const Vehicle<S> vehicle(nerov_parameters<S>());
  SimulationConfig<S> cfg = configurations<S>()[1].second;  // noise
  cfg.duration = S(1);
  Simulator<S> sim;
  ASSERT_TRUE(Simulator<S>::create(vehicle, cfg, sim, 2).ok());
  const S theta[2] = {S(1), S(2)};
  ControllerReport<S> good;
  good.parameters = theta;
  good.parameter_count = 2;
  ASSERT_EQ(sim.step(Vector6<S>::Ones(), good), Status::ok);
  const Observation<S> before = sim.observation();
  const Vector6<S> eta = sim.eta();

  ControllerReport<S> wrong_count = good;
  wrong_count.parameter_count = 1;
  EXPECT_EQ(sim.step(Vector6<S>::Ones(), wrong_count), Status::invalid_argument);
  ControllerReport<S> no_parameters = good;
  no_parameters.parameters = nullptr;
  EXPECT_EQ(sim.step(Vector6<S>::Ones(), no_parameters), Status::invalid_argument);
  Vector6<S> nan_tau = Vector6<S>::Ones();
  nan_tau(2) = std::numeric_limits<S>::quiet_NaN();
  EXPECT_EQ(sim.step(nan_tau, good), Status::non_finite_input);
  EXPECT_EQ(sim.steps(), 1);
  EXPECT_EQ(sim.eta(), eta);
  EXPECT_EQ(sim.observation().eta, before.eta);

  // A refused step's force is not applied, NaN or not: the policy decides.
  ControllerReport<S> refused = good;
  refused.status = Status::non_finite_input;
  EXPECT_EQ(sim.step(nan_tau, refused), Status::ok);
  EXPECT_EQ(sim.steps(), 2);
  while (!sim.done()) sim.step(Vector6<S>::Zero(), good);
  const SimulationResult<S> full = sim.result();
  EXPECT_EQ(full.steps, 6);
  EXPECT_TRUE(full.tau_demanded.row(1).isZero(S(0)));
  EXPECT_EQ(full.controller_status(1), static_cast<std::uint8_t>(Status::non_finite_input));
  EXPECT_EQ(full.theta(3, 1), S(2));
  EXPECT_EQ(sim.step(Vector6<S>::Zero(), good), Status::invalid_argument);
  expect_same_run(sim.result(), full, "after done");

  Simulator<S> empty;
  EXPECT_TRUE(empty.done());
  EXPECT_EQ(empty.step(Vector6<S>::Zero(), ControllerReport<S>{}), Status::invalid_argument);
  EXPECT_STREQ(Simulator<S>::create(vehicle, cfg, sim, -1).field, "logged_parameters");
  EXPECT_STREQ(Simulator<S>::create(Vehicle<S>{}, cfg, sim).field, "vehicle");
  EXPECT_EQ(sim.steps(), 6);  // a failed create leaves the simulator as it was
}

// A finite force near the scalar's largest value is logged finite: the row's
// tau_applied is the mean of its substeps, not their sum divided afterwards
// (four substeps of 0.7 max summed first are inf; libFuzzer found it in float).
TYPED_TEST(SimulatorTest, TheMeanOfHugeFiniteForcesIsFinite) {
  using S = TypeParam;
  SimulationConfig<S> cfg = square<S>();
  cfg.substeps = 4;
  // Short enough that the force moves the plant by a finite amount.
  cfg.dt = S(1000) / std::numeric_limits<S>::max();
  cfg.duration = cfg.dt;
  Simulator<S> sim;
  const ValidationError e = Simulator<S>::create(Vehicle<S>(nerov_parameters<S>()), cfg, sim);
  ASSERT_TRUE(e.ok()) << e.field << " " << e.expected;
  Vector6<S> tau = Vector6<S>::Zero();
  tau(0) = S(0.7) * std::numeric_limits<S>::max();
  tau(1) = -tau(0);
  ASSERT_EQ(sim.step(tau, ControllerReport<S>{}), Status::ok);
  const SimulationResult<S> r = sim.result();
  EXPECT_EQ(r.tau_applied.row(0).transpose(), tau);
  EXPECT_TRUE(r.eta.allFinite() && r.nu.allFinite());
}

TYPED_TEST(SimulatorTest, ANewSeedChangesTheNoiseOnly) {
  using S = TypeParam;
  const Vehicle<S> vehicle(nerov_parameters<S>());
  const SimulationConfig<S> cfg = configurations<S>()[1].second;  // noise
  Simulator<S> sim;
  ASSERT_TRUE(Simulator<S>::create(vehicle, cfg, sim).ok());
  auto c = make_pd<S>();
  drive(sim, c);
  const SimulationResult<S> first = sim.result();
  sim.reset(cfg.seed + 1);
  c.reset();
  drive(sim, c);
  const SimulationResult<S> second = sim.result();
  EXPECT_EQ(first.eta.row(0), second.eta.row(0));
  EXPECT_NE(first.eta.row(5), second.eta.row(5));
  EXPECT_NE(first.tau_demanded.row(0), second.tau_demanded.row(0));  // measured with other noise
  EXPECT_EQ(first.eta_d, second.eta_d);  // the reference does not see the noise
}

// The configurations above exercise what they claim to: otherwise the
// comparison would prove little.
TYPED_TEST(SimulatorTest, ComparisonConfigurationsReachTheirFeatures) {
  using S = TypeParam;
  for_each_run<S>(make_pd<S>, [](const std::string& label, const SimulationConfig<S>& cfg,
                                  const Vehicle<S>&, const SimulationResult<S>& r) {
    std::uint8_t bits = 0;
    for (Eigen::Index k = 0; k < r.steps; ++k) bits |= r.faults(k);
    if (!cfg.sensor_faults.empty()) {
      EXPECT_EQ(bits & (fault_bits::freeze | fault_bits::dropout | fault_bits::noise_burst),
                fault_bits::freeze | fault_bits::dropout | fault_bits::noise_burst)
          << label;
      EXPECT_GT((r.controller_status.array() != 0).count(), 5) << label;
    }
    if (!cfg.thruster_failures.empty()) {
      EXPECT_TRUE(bits & fault_bits::thruster) << label;
    }
    EXPECT_EQ(r.diverged, label == std::string("divergence")) << label;
    if (r.diverged) {
      EXPECT_LT(r.steps, 40) << label;
    }
  });
}

}  // namespace
