// The exhaustive hostile-input sweep (see test_reliability_controllers.cpp)
// of the configurations (every validator names the bad field), the
// thrusters and the closed loop.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "neurov/neurov.hpp"
#include "controller_state.hpp"
#include "held_command.hpp"
#include "reliability_fixtures.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using namespace neurov_test;

NEUROV_SCALAR_SUITE(ReliabilityTest);


/// Sets one parameter of a default Config to `bad` with `set` and expects
/// validate() to refuse it, naming `field`.
template <typename Config, typename S, typename Set>
void expect_refused(const char* what, S bad, Set set, const char* field) {
  Config c;
  set(c, bad);
  const ValidationError e = validate(c);
  ASSERT_FALSE(e.ok()) << what << " = " << bad;
  EXPECT_STREQ(e.field, field) << what << " = " << bad;
}

// Zero or negative gains and time steps, for every controller's config.
TYPED_TEST(ReliabilityTest, ControllerConfigurationsRefuseZeroOrNegativeGainsAndDt) {
  using S = TypeParam;
  using NN = NNAdaptiveConfig<S>;
  using Linear = LinearAdaptiveConfig<S>;
  using PID = PIDConfig<S>;
  using SMC = SlidingModeConfig<S>;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  for (const S bad : {S(0), S(-1), nan}) {
    expect_refused<NN>("NN dt", bad, [](NN& c, S v) { c.dt = v; }, "dt");
    expect_refused<NN>("NN lambda", bad, [](NN& c, S v) { c.lambda(1) = v; }, "lambda");
    expect_refused<Linear>("linear dt", bad, [](Linear& c, S v) { c.dt = v; }, "dt");
    expect_refused<Linear>("linear lambda", bad, [](Linear& c, S v) { c.lambda(5) = v; }, "lambda");
    expect_refused<PID>("PID dt", bad, [](PID& c, S v) { c.dt = v; }, "dt");
    expect_refused<PID>("PID integral_limit", bad, [](PID& c, S v) { c.integral_limit(0) = v; },
                        "integral_limit");
    expect_refused<SMC>("SMC phi", bad, [](SMC& c, S v) { c.phi(2) = v; }, "phi");
    expect_refused<SMC>("SMC lambda", bad, [](SMC& c, S v) { c.lambda(0) = v; }, "lambda");
  }
  for (const S bad : {S(-1), nan, -std::numeric_limits<S>::infinity()}) {
    expect_refused<NN>("NN kd", bad, [](NN& c, S v) { c.kd(4) = v; }, "kd");
    expect_refused<NN>("NN gamma", bad, [](NN& c, S v) { c.gamma = v; }, "gamma");
    expect_refused<Linear>("linear gamma", bad, [](Linear& c, S v) { c.gamma(7) = v; }, "gamma");
    using PD = PDConfig<S>;
    expect_refused<PD>("PD kp", bad, [](PD& c, S v) { c.kp(0) = v; }, "kp");
    expect_refused<PD>("PD kd", bad, [](PD& c, S v) { c.kd(5) = v; }, "kd");
    expect_refused<PID>("PID ki", bad, [](PID& c, S v) { c.ki(2) = v; }, "ki");
    expect_refused<SMC>("SMC k", bad, [](SMC& c, S v) { c.k(1) = v; }, "k");
  }
  ReferenceModel<S> r;
  EXPECT_STREQ(ReferenceModel<S>::create(Vector6<S>::Zero(), Vector6<S>::Ones(),
                                         Vector6<S>::Zero(), r)
                   .field,
               "lambda_d");
  EXPECT_STREQ(ReferenceModel<S>::create(Vector6<S>::Ones(), -Vector6<S>::Ones(),
                                         Vector6<S>::Zero(), r)
                   .field,
               "omega");
}

// Non-symmetric or indefinite mass matrices, in every way they can come about.
// An indefinite part may be named itself or as the sum M it spoils
// ("mass_matrix"); either names what is wrong.
TYPED_TEST(ReliabilityTest, VehicleRefusesNonSymmetricOrIndefiniteMassMatrices) {
  using S = TypeParam;
  using Case = Refusal<VehicleParameters<S>>;
  const Case cases[] = {
      {"non-symmetric inertia", [](auto& p) { p.inertia(0, 2) = S(3); }, "inertia"},
      {"non-symmetric added mass", [](auto& p) { p.added_mass(5, 1) = S(-4); }, "added_mass"},
      {"negative definite added mass", [](auto& p) { p.added_mass *= S(-10); }, "added_mass",
       "mass_matrix"},
      {"indefinite inertia", [](auto& p) { p.inertia(1, 1) = S(-200); }, "inertia", "mass_matrix"},
      {"symmetric but indefinite coupling",
       [](auto& p) {
         p.added_mass(0, 1) = p.added_mass(1, 0) = S(1000);
       },
       "added_mass", "mass_matrix"},
      {"every part definite, M_RB + M_A not (r_g 1 m off)",
       [](auto& p) { p.centre_of_gravity.z() = S(1); }, "mass_matrix"},
      {"zero mass", [](auto& p) { p.mass = S(0); }, "mass"},
      {"negative mass", [](auto& p) { p.mass = S(-185); }, "mass"},
      {"NaN inertia", [](auto& p) { p.inertia(2, 2) = std::numeric_limits<S>::quiet_NaN(); },
       "inertia"},
      {"infinite added mass",
       [](auto& p) { p.added_mass(3, 3) = std::numeric_limits<S>::infinity(); }, "added_mass"},
  };
  for (const Case& c : cases) {
    Vehicle<S> v;
    EXPECT_TRUE(c.named_by(Vehicle<S>::create(c.applied_to(nerov_parameters<S>()), v)));
    EXPECT_FALSE(v.valid()) << c.what;
  }
}

// ----------------------------------------------------------------- thrusters


// A finite but enormous demanded wrench (a controller fed a glitching sensor)
// must still give thrusts within their limits: never NaN, never beyond.
TYPED_TEST(ReliabilityTest, ThrusterCommandsStayWithinLimitsForHugeFiniteWrenches) {
  using S = TypeParam;
  for (const Saturation sat : {Saturation::scale, Saturation::clip}) {
    ThrusterConfig<S> cfg = nerov_thrusters<S>();
    cfg.saturation = sat;
    Thrusters<S> t;
    ASSERT_TRUE(Thrusters<S>::create(cfg, t).ok());
    for (int i = 0; i < 6; ++i)
      for (const S v : hostile_values<S>()) {
        if (!std::isfinite(v)) continue;
        for (const S other : {S(0), S(100), -std::numeric_limits<S>::max()}) {
          Vector6<S> tau = Vector6<S>::Constant(other);
          tau(i) = v;
          t.command(tau);
          t.advance(S(0.02));
          const std::string what = std::string(sat == Saturation::scale ? "scale" : "clip") +
                                   ", tau[" + std::to_string(i) + "] = " + show(v) +
                                   ", others " + show(other);
          EXPECT_TRUE(t.commanded().allFinite()) << what << ": " << t.commanded().transpose();
          EXPECT_TRUE((t.commanded().array() <= cfg.max_thrust.array()).all() &&
                      (t.commanded().array() >= cfg.min_thrust.array()).all())
              << what << ": " << t.commanded().transpose();
          EXPECT_TRUE(t.wrench().allFinite()) << what;
        }
      }
  }
}

TYPED_TEST(ReliabilityTest, ThrusterConfigurationNamesTheBadField) {
  using S = TypeParam;
  using Case = Refusal<ThrusterConfig<S>>;
  const Case cases[] = {
      {"five thrusters", [](auto& c) { c.matrix.conservativeResize(6, 5); }, "thrusters.matrix"},
      {"NaN in B", [](auto& c) { c.matrix(2, 3) = std::numeric_limits<S>::quiet_NaN(); },
       "thrusters.matrix"},
      {"rank-deficient B", [](auto& c) { c.matrix.col(5) = c.matrix.col(4); },
       "thrusters.matrix"},
      {"limits of the wrong size", [](auto& c) { c.max_thrust.conservativeResize(5); },
       "thrusters.max_thrust"},
      {"min above max", [](auto& c) { c.min_thrust(1) = S(300); }, "thrusters.max_thrust"},
      {"infinite limit", [](auto& c) { c.max_thrust(0) = std::numeric_limits<S>::infinity(); },
       "thrusters.max_thrust"},
      {"zero weight",
       [](auto& c) {
         c.weights = ThrusterConfig<S>::Vector::Ones(6);
         c.weights(2) = S(0);
       },
       "thrusters.weights"},
      {"negative time constant", [](auto& c) { c.time_constant = S(-0.1); },
       "thrusters.time_constant"},
  };
  for (const Case& k : cases) {
    Thrusters<S> t;
    EXPECT_TRUE(k.named_by(Thrusters<S>::create(k.applied_to(nerov_thrusters<S>()), t)));
  }
}

// -------------------------------------------------------------- closed loop

template <typename S>
SimulationConfig<S> loop_config() {
  SimulationConfig<S> c;
  c.duration = S(2);
  c.command = held<S>(Vector6<S>::UnitX());
  return c;
}

/// The run on NEROV's thrusters.
template <typename S>
SimulationConfig<S>& on_thrusters(SimulationConfig<S>& c) {
  c.use_thrusters = true;
  c.thrusters = nerov_thrusters<S>();
  return c;
}

TYPED_TEST(ReliabilityTest, SimulationConfigurationNamesTheBadField) {
  using S = TypeParam;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  const Vehicle<S> vehicle(nerov_parameters<S>());
  struct Case {
    const char* what;
    std::function<void(SimulationConfig<S>&)> mutate;
    const char* field;
  };
  const std::vector<Case> cases = {
      {"zero dt", [](auto& c) { c.dt = S(0); }, "dt"},
      {"negative dt", [](auto& c) { c.dt = S(-0.2); }, "dt"},
      {"dt above kMaxStep", [](auto& c) { c.dt = S(10.5); }, "dt"},
      {"zero substeps", [](auto& c) { c.substeps = 0; }, "substeps"},
      {"negative duration", [](auto& c) { c.duration = S(-1); }, "duration"},
      // More than 1e8 steps: dt's fault while some dt up to kMaxStep would do, else duration's.
      {"too many steps at any dt", [](auto& c) { c.duration = S(2e9); }, "duration"},
      {"too many steps of a tiny dt", [](auto& c) { c.dt = S(1e-9); }, "dt"},
      {"the smallest denormal dt", [](auto& c) { c.dt = std::numeric_limits<S>::denorm_min(); }, "dt"},
      {"NaN initial pose", [nan](auto& c) { c.eta0(2) = nan; }, "eta0"},
      {"initial pitch at 90 deg", [](auto& c) { c.eta0(4) = static_cast<S>(kPi / 2); }, "eta0"},
      {"infinite initial velocity",
       [](auto& c) { c.nu0(5) = std::numeric_limits<S>::infinity(); }, "nu0"},
      {"no command",
       [](auto& c) {
         c.command.times.resize(0);
         c.command.poses.resize(0, 6);
       },
       "command.times"},
      {"times and poses mismatched", [](auto& c) { c.command.poses.setZero(2, 6); },
       "command.poses"},
      {"NaN commanded pose", [nan](auto& c) { c.command.poses(0, 3) = nan; }, "command.poses"},
      {"times not increasing",
       [](auto& c) {
         c.command.times.resize(2);
         c.command.times << S(1), S(1);
         c.command.poses.setZero(2, 6);
       },
       "command.times"},
      {"zero reference damping", [](auto& c) { c.lambda_d(0) = S(0); }, "lambda_d"},
      {"negative reference stiffness", [](auto& c) { c.omega(1) = S(-1); }, "omega"},
      {"disturbance in DOF 6", [](auto& c) { c.disturbances.push_back({6, S(1), S(0.1), S(0), S(0)}); },
       "disturbances.dof"},
      {"NaN disturbance amplitude",
       [nan](auto& c) { c.disturbances.push_back({5, nan, S(0.1), S(0), S(0)}); }, "disturbances"},
      {"negative noise", [](auto& c) { c.noise_nu(0) = S(-0.1); }, "noise_nu"},
      {"NaN current", [nan](auto& c) { c.current(0) = nan; }, "current"},
      {"sensor fault ending before it starts",
       [](auto& c) {
         SensorFault<S> f;
         f.start = S(2);
         f.end = S(1);
         c.sensor_faults.push_back(f);
       },
       "sensor_faults.end"},
      {"unknown sensor fault kind",
       [](auto& c) {
         SensorFault<S> f;
         f.kind = static_cast<SensorFaultKind>(7);
         f.end = S(1);
         c.sensor_faults.push_back(f);
       },
       "sensor_faults.kind"},
      {"current steps out of order",
       [](auto& c) {
         c.current_steps.push_back({S(5), Vector3<S>::Zero()});
         c.current_steps.push_back({S(4), Vector3<S>::Zero()});
       },
       "current_steps.time"},
      {"thruster failure without thrusters",
       [](auto& c) { c.thruster_failures.push_back({0, S(0), S(1)}); }, "thruster_failures"},
      {"thruster failure of thruster 6",
       [](auto& c) { on_thrusters(c).thruster_failures.push_back({6, S(0), S(1)}); },
       "thruster_failures.index"},
      {"efficiency above one",
       [](auto& c) { on_thrusters(c).thruster_failures.push_back({0, S(1.5), S(1)}); },
       "thruster_failures.efficiency"},
      {"bad thruster layout", [](auto& c) { on_thrusters(c).thrusters.matrix.col(1).setZero(); },
       "thrusters.matrix"},
  };
  for (const Case& k : cases) {
    SimulationConfig<S> cfg = loop_config<S>();
    k.mutate(cfg);
    PDController<S> ctl = pd<S>();
    SimulationResult<S> out;
    const ValidationError e = simulate(vehicle, ctl, cfg, out);
    ASSERT_FALSE(e.ok()) << k.what;
    EXPECT_STREQ(e.field, k.field) << k.what;
    EXPECT_EQ(out.steps, 0) << k.what;
  }
  PDController<S> ctl = pd<S>();
  SimulationResult<S> out;
  EXPECT_STREQ(simulate(Vehicle<S>{}, ctl, loop_config<S>(), out).field, "vehicle");
}

/// The message of a refusal, to check that it gives the limit.
std::string message_of(const ValidationError& e) {
  char buf[256];
  e.format(buf, sizeof buf);
  return buf;
}

// Every count a file can give has a maximum, refused before anything is
// allocated or run, the message giving the limit (issue 23: 2e9 substeps ran
// for ever; 10^9 wave components were refused without saying the limit).
TYPED_TEST(ReliabilityTest, CountsAboveTheirMaximumAreRefusedNamingTheLimit) {
  using S = TypeParam;
  for (const int substeps : {kMaxSubsteps + 1, 2000000000, std::numeric_limits<int>::max()}) {
    SimulationConfig<S> c = loop_config<S>();
    c.substeps = substeps;
    const ValidationError e = validate(c);
    ASSERT_STREQ(e.field, "substeps") << substeps;
    EXPECT_NE(message_of(e).find("1..10000"), std::string::npos) << message_of(e);
  }
  SimulationConfig<S> at_limit = loop_config<S>();
  at_limit.substeps = kMaxSubsteps;
  EXPECT_TRUE(validate(at_limit).ok());

  for (const int components : {kMaxWaveComponents + 1, 1000000000}) {
    SimulationConfig<S> c = loop_config<S>();
    c.waves = WaveConfig<S>{};
    c.waves->components = components;
    const ValidationError e = validate(c);
    ASSERT_STREQ(e.field, "components") << components;
    EXPECT_NE(message_of(e).find("within [1, 512]"), std::string::npos) << message_of(e);
  }

  // One centre over the limit: 65537 x 2 numbers, refused before the
  // network copies or packs them.
  using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  RbfNetwork<S> net;
  const ValidationError e = RbfNetwork<S>::create(Mat::Zero(kMaxCentres + 1, 2),
                                                  Vec::Ones(kMaxCentres + 1), net);
  ASSERT_STREQ(e.field, "centres");
  EXPECT_NE(message_of(e).find("at most 65536 centres"), std::string::npos) << message_of(e);
  EXPECT_FALSE(net.configured());
  EXPECT_TRUE(RbfNetwork<S>::create(Mat::Zero(kMaxCentres, 2), Vec::Ones(kMaxCentres), net).ok());
  EXPECT_EQ(net.centres_count(), kMaxCentres);
}

// The loop under a sensor dropout: every refused step is recorded with its
// status, the demanded tau is zero (policy "zero") or the last accepted one
// (policy "hold"), the plant never sees a NaN, and the controller's weights
// do not move while it is blind.
TYPED_TEST(ReliabilityTest, LoopReportsRefusedStepsAndKeepsTheWeightsDuringADropout) {
  using S = TypeParam;
  const Vehicle<S> vehicle(nerov_parameters<S>());
  for (const RefusedStepPolicy policy : {RefusedStepPolicy::zero, RefusedStepPolicy::hold}) {
    SimulationConfig<S> cfg = loop_config<S>();
    cfg.duration = S(20);
    cfg.refused_step_policy = policy;
    SensorFault<S> f;
    f.kind = SensorFaultKind::dropout;
    f.start = S(5);
    f.end = S(8);
    f.eta = false;  // only the velocity drops out
    cfg.sensor_faults.push_back(f);
    auto ctl = nn<S>(RobustModification::sigma, 9);
    SimulationResult<S> r;
    ASSERT_TRUE(simulate(vehicle, ctl, cfg, r).ok());
    ASSERT_FALSE(r.diverged);
    ASSERT_TRUE(r.eta.allFinite() && r.nu.allFinite() && r.tau_applied.allFinite());
    int refused = 0;
    for (Eigen::Index k = 0; k < r.steps; ++k) {
      const bool in_fault = r.t(k) >= f.start && r.t(k) < f.end;
      EXPECT_EQ(r.faults(k) == fault_bits::dropout, in_fault) << "t = " << r.t(k);
      EXPECT_EQ(r.controller_status(k) == static_cast<std::uint8_t>(Status::non_finite_input),
                in_fault)
          << "t = " << r.t(k);
      if (!in_fault) continue;
      ++refused;
      EXPECT_EQ(r.adaptive_norm(k), r.adaptive_norm(k - 1)) << "weights moved while blind";
      const Vector6<S> expected = policy == RefusedStepPolicy::zero
                                      ? Vector6<S>::Zero().eval()
                                      : Vector6<S>(r.tau_demanded.row(k - 1).transpose());
      EXPECT_TRUE((r.tau_demanded.row(k).transpose().array() == expected.array()).all())
          << "t = " << r.t(k);
    }
    EXPECT_GE(refused, 14);  // 3 s at 5 Hz, give or take the rounding of k dt
  }
}

}  // namespace
