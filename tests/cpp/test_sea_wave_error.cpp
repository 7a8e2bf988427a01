// What following the waves once per control period costs in accuracy.
// The Simulator evaluates the wave kinematics at the vehicle once per control
// period (at the position predicted for its end) with their rates along the
// vehicle's path, and interpolates the flow in time through the substeps and
// RK4 stages. The reference here evaluates the direct sum (Waves::evaluate)
// at every RK4 stage, at the stage's own time and position, takes the rate
// of the flow along the stage's path as the plant does (the local
// acceleration plus the change along its velocity), and integrates the same
// plant (derivative_in_flow) with its own RK4. Both fly the same
// station-keeping law on the true state around a moving target for 600 s,
// in sea states 3 to 5; the largest and RMS differences of the flow and of
// the trajectory are recorded and bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <ostream>
#include <string>

#include "neurov/neurov.hpp"
#include "held_command.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::record;
using Vec3 = Vector3<double>;
using Vec6 = Vector6<double>;

struct Sea {
  const char* name;
  double hs, tp, spreading;
};

void PrintTo(const Sea& s, std::ostream* os) { *os << s.name; }

constexpr double kDuration = 600.0, kDt = 0.2;
constexpr int kSubsteps = 10;
constexpr double kDepth = 6.0;  // below 1.2 Hs = 3.9 m of sea state 5

/// The target: a 30 m circle at 1 m/s, heading along it, bobbing 1 m.
void target(double t, Vec6& eta_d, Vec6& eta_d_dot) {
  const double radius = 30.0, w = 1.0 / radius;
  eta_d << radius * std::sin(w * t), radius * (1 - std::cos(w * t)), kDepth + std::sin(0.05 * t),
      0, 0, w * t;
  eta_d_dot << std::cos(w * t), std::sin(w * t), 0.05 * std::cos(0.05 * t), 0, 0, w;
}

/// A PD law on the true state (no noise, no estimator), the same for both.
Vec6 control(double t, const Vec6& eta, const Vec6& nu) {
  Vec6 eta_d, eta_d_dot;
  target(t, eta_d, eta_d_dot);
  const Matrix3<double> r = rotation(EulerTrig<double>::from_pose(eta));
  Vec6 e;
  e.head<3>() = r.transpose() * (eta_d.head<3>() - eta.head<3>());
  e.tail<3>() = eta_d.tail<3>() - eta.tail<3>();
  e(5) = std::remainder(e(5), 2 * 3.14159265358979323846);
  Vec6 e_dot;
  e_dot.head<3>() = r.transpose() * eta_d_dot.head<3>() - nu.head<3>();
  e_dot.tail<3>() = eta_d_dot.tail<3>() - nu.tail<3>();
  // Gains well inside what a 5 Hz zero-order hold allows (kd dt / inertia
  // below 1 on every axis: stiffer, roll rings from period to period).
  Vec6 kp, kd;
  kp << 400, 400, 400, 100, 100, 100;
  kd << 600, 600, 600, 100, 100, 100;
  return kp.cwiseProduct(e) + kd.cwiseProduct(e_dot);
}

WaveConfig<double> waves_of(const Sea& s) {
  WaveConfig<double> w;  // JONSWAP, gamma 3.3, 200 components
  w.hs = s.hs;
  w.tp = s.tp;
  w.spreading = s.spreading;
  w.direction = 30.0;
  return w;
}

class WaveFollowingError : public ::testing::TestWithParam<Sea> {};

TEST_P(WaveFollowingError, AgainstTheDirectSumAtEveryStage) {
  const Sea sea = GetParam();
  const Vehicle<double> vehicle(nerov_parameters<double>());
  SimulationConfig<double> c;
  c.dt = kDt;
  c.substeps = kSubsteps;
  c.duration = kDuration;
  c.seed = 11;
  Vec6 eta_d, eta_d_dot;
  target(0.0, eta_d, eta_d_dot);
  c.eta0 = eta_d;
  c.nu0 << 1, 0, 0.05, 0, 0, 1.0 / 30;
  c.command = neurov_test::held(c.eta0);
  c.waves = waves_of(sea);

  // The fast path: the Simulator.
  Simulator<double> sim;
  ASSERT_TRUE(Simulator<double>::create(vehicle, c, sim).ok());
  while (!sim.done()) {
    const double t = sim.observation().t;
    ASSERT_EQ(sim.step(control(t, sim.eta(), sim.nu()), ControllerReport<double>{}), Status::ok);
  }
  SimulationResult<double> fast;
  sim.release_result(fast);

  // The reference: the direct sum at every RK4 stage, from the same
  // realisation (the waves stream of the same seed).
  auto waves = std::make_unique<Waves<double>>();
  ASSERT_TRUE(Waves<double>::create(*c.waves, c.seed, *waves).ok());
  const double displaced = vehicle.parameters().buoyancy / standard_gravity;
  const auto f = [&](double t, const Vec6& eta, const Vec6& nu, const Vec6& tau, Vec6& eta_dot,
                     Vec6& nu_dot) {
    WaveKinematics<double> k, ahead, behind;
    const Vec3 p = eta.head<3>();
    EXPECT_EQ(waves->evaluate(t, p, k), Status::ok);
    // The rate of the flow along the stage's path: the local acceleration
    // plus (p_dot . grad) v, by central differences 0.1 mm either side
    // (truncation (k delta)^2 / 6 < 1e-8, rounding < 1e-12 of the flow).
    const Vec3 p_dot = rotation(EulerTrig<double>::from_pose(eta)) * nu.head<3>();
    const double speed = p_dot.norm(), delta = 1e-4;
    Vec3 convective = Vec3::Zero();
    if (speed > 0) {
      const Vec3 d = p_dot / speed;
      EXPECT_EQ(waves->evaluate(t, p + delta * d, ahead), Status::ok);
      EXPECT_EQ(waves->evaluate(t, p - delta * d, behind), Status::ok);
      convective = speed * (ahead.velocity - behind.velocity) / (2 * delta);
    }
    FluidFlow<double> flow;
    flow.velocity = k.velocity;
    flow.acceleration = k.acceleration + convective;
    flow.displaced_mass = displaced;
    EXPECT_EQ(derivative_in_flow(vehicle, eta, nu, tau, flow, eta_dot, nu_dot), Status::ok);
  };
  const Eigen::Index rows = fast.t.size();
  ASSERT_EQ(rows, static_cast<Eigen::Index>(kDuration / kDt) + 1);
  Vec6 eta = c.eta0, nu = c.nu0;
  const double h = kDt / kSubsteps;
  double max_flow = 0, err_flow = 0, sq_flow = 0, err_row_flow = 0;
  double err_pos = 0, sq_pos = 0, err_vel = 0, sq_vel = 0, max_speed = 0;
  for (Eigen::Index k = 0; k < rows; ++k) {
    const double t = k * kDt;
    // The flow the plant met at t_k in the fast run (the start of its
    // period) against the direct sum where the vehicle really was.
    WaveKinematics<double> at_fast, at_ref;
    ASSERT_EQ(waves->evaluate(t, fast.eta.row(k).head<3>().transpose(), at_fast), Status::ok);
    err_row_flow = std::max(err_row_flow,
                            (fast.wave_velocity.row(k).transpose() - at_fast.velocity).norm());
    // The flow met and the trajectories of the two runs.
    ASSERT_EQ(waves->evaluate(t, eta.head<3>(), at_ref), Status::ok);
    const double d_flow = (fast.wave_velocity.row(k).transpose() - at_ref.velocity).norm();
    const double d_pos = (fast.eta.row(k).head<3>().transpose() - eta.head<3>()).norm();
    const double d_vel = (fast.nu.row(k).transpose() - nu).norm();
    max_flow = std::max(max_flow, at_ref.velocity.norm());
    max_speed = std::max(max_speed, nu.head<3>().norm());
    err_flow = std::max(err_flow, d_flow);
    err_pos = std::max(err_pos, d_pos);
    err_vel = std::max(err_vel, d_vel);
    sq_flow += d_flow * d_flow;
    sq_pos += d_pos * d_pos;
    sq_vel += d_vel * d_vel;
    if (k + 1 == rows) break;
    const Vec6 tau = control(t, eta, nu);
    for (int j = 0; j < kSubsteps; ++j) {  // classical RK4
      const double ts = t + j * h;
      Vec6 e1, n1, e2, n2, e3, n3, e4, n4;
      f(ts, eta, nu, tau, e1, n1);
      f(ts + h / 2, eta + h / 2 * e1, nu + h / 2 * n1, tau, e2, n2);
      f(ts + h / 2, eta + h / 2 * e2, nu + h / 2 * n2, tau, e3, n3);
      f(ts + h, eta + h * e3, nu + h * n3, tau, e4, n4);
      eta += h / 6 * (e1 + 2 * e2 + 2 * e3 + e4);
      nu += h / 6 * (n1 + 2 * n2 + 2 * n3 + n4);
    }
  }
  const double n = static_cast<double>(rows);
  const std::string s = sea.name;
  record(s + "_max_orbital_velocity", max_flow);
  record(s + "_max_speed", max_speed);
  record(s + "_flow_error_at_rows_max", err_row_flow);
  record(s + "_flow_difference_max", err_flow);
  record(s + "_flow_difference_rms", std::sqrt(sq_flow / n));
  record(s + "_position_difference_max", err_pos);
  record(s + "_position_difference_rms", std::sqrt(sq_pos / n));
  record(s + "_velocity_difference_max", err_vel);
  record(s + "_velocity_difference_rms", std::sqrt(sq_vel / n));
  EXPECT_GT(max_speed, 0.9);  // the vehicle does move through the waves
  EXPECT_GT(max_flow, 0.1 * sea.hs);
  // Bounds. Held constant over a period instead, the flow would be off by
  // up to w_p dt = 0.13 to 0.17 of itself (the peak frequencies of these
  // seas). Left: the cubic in time, (w dt)^4 / 384 of each component (1e-6
  // at the peak; the short waves, w dt up to 0.9, are damped by e^(-k z) at
  // this depth), and the end position predicted from the velocity and
  // acceleration at the period's start, off by about dt^3 |jerk| / 6 when
  // the force steps, a phase error k dp. Measured (test properties): at most
  // 2.1e-4 of the largest orbital velocity (sea state 5; 9e-5 in 4, 7e-5
  // in 3). The bound, 2e-3, is ten times that and 65 times below the error
  // of holding the flow over a period.
  EXPECT_LT(err_row_flow, 2e-3 * max_flow);
  EXPECT_LT(err_flow, 2e-3 * max_flow);
  // The trajectory: a flow error of that size, filtered by the closed loop
  // (bandwidth about 1.4 rad/s), moves the vehicle's velocity by less than
  // itself and its position by less than its size over one second
  // (measured: 2.1e-4 m/s, 2.8e-4 m at most).
  EXPECT_LT(err_vel, 2e-3 * max_flow);
  EXPECT_LT(err_pos, 2e-3 * max_flow * 1.0);
}

INSTANTIATE_TEST_SUITE_P(SeaStates, WaveFollowingError,
                         ::testing::Values(Sea{"sea_state_3", 0.88, 7.5, 0.0},
                                           Sea{"sea_state_4", 1.88, 8.8, 2.0},
                                           Sea{"sea_state_5", 3.25, 9.7, 0.0}),
                         [](const ::testing::TestParamInfo<Sea>& i) {
                           return std::string(i.param.name);
                         });

}  // namespace
