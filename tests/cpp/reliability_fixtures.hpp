// What the reliability tests (test_reliability_*.cpp) share: the typed
// fixture, the hostile values swept into every entry, and one regularly
// configured controller of each kind.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "neurov/neurov.hpp"
#include "test_support.hpp"

namespace neurov_test {

/// A hostile change to a valid Config, what it is, and the field its refusal
/// names (where two names are right, either).
template <typename Config>
struct Refusal {
  const char* what;
  void (*mutate)(Config&);
  const char* field;
  const char* or_field = nullptr;

  Config applied_to(Config c) const {
    mutate(c);
    return c;
  }

  /// e refuses, naming field (or or_field).
  ::testing::AssertionResult named_by(const neurov::ValidationError& e) const {
    if (e.ok()) return ::testing::AssertionFailure() << what << ": accepted";
    const std::string f = e.field;
    if (f == field || (or_field != nullptr && f == or_field)) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << what << ": named " << f;
  }
};

/// Values no sane sensor or caller produces but a broken one can.
template <typename S>
std::vector<S> hostile_values() {
  using L = std::numeric_limits<S>;
  return {L::quiet_NaN(),       -L::quiet_NaN(),     L::infinity(),
          -L::infinity(),       L::max(),            L::lowest(),
          std::sqrt(L::max()),  -std::sqrt(L::max()), static_cast<S>(1e15),
          static_cast<S>(-1e9), L::denorm_min(),     static_cast<S>(-0.0)};
}

template <typename S>
std::string show(S v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(v));
  return buf;
}

// -------------------------------------------- controllers of a regular setup

template <typename S, int N = Eigen::Dynamic>
neurov::NNAdaptiveController<S, N> nn(neurov::RobustModification mod, std::uint32_t seed, S dead_zone = S(0)) {
  using Ctl = neurov::NNAdaptiveController<S, N>;
  neurov_test::Rng rng(seed);
  const int n = N == Eigen::Dynamic ? 16 : N;
  typename Ctl::Network::CentreMatrix centres(n, neurov::kNNInputs);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < neurov::kNNInputs; ++i) centres(j, i) = rng.uniform<S>(-1.5, 1.5);
  typename Ctl::Network net;
  EXPECT_TRUE(Ctl::Network::create(centres, Ctl::BasisVector::Constant(n, S(2)), net).ok());
  typename Ctl::WeightMatrix w(6, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < 6; ++i) w(i, j) = rng.uniform<S>(-20, 20);
  EXPECT_TRUE(net.set_weights(w));
  neurov::NNAdaptiveConfig<S> cfg;
  cfg.lambda.setConstant(S(0.8));
  cfg.kd << S(200), S(200), S(200), S(50), S(50), S(50);
  cfg.gamma = S(2);
  cfg.dt = S(0.2);
  cfg.modification = mod;
  cfg.sigma_m = S(0.1);
  cfg.kappa = S(0.05);
  cfg.w_max = S(100);
  cfg.dead_zone = dead_zone;
  Ctl c;
  EXPECT_TRUE(Ctl::create(net, cfg, c).ok());
  return c;
}

template <typename S>
neurov::LinearAdaptiveController<S> linear() {
  neurov::LinearAdaptiveConfig<S> cfg;
  cfg.kd << S(200), S(200), S(200), S(50), S(50), S(50);
  neurov::ParameterVector<S> theta;
  EXPECT_TRUE(neurov::regressor_parameters(neurov::nerov_parameters<S>(), theta).ok());
  cfg.theta0 = S(0.8) * theta;
  return neurov::LinearAdaptiveController<S>(cfg);
}

/// The PD's gains: the PID keeps them and adds an integral.
template <template <typename> class Config, typename S>
Config<S> with_pd_gains() {
  Config<S> cfg;
  cfg.kp.setConstant(S(100));
  cfg.kd.setConstant(S(200));
  return cfg;
}

template <typename S>
neurov::PDController<S> pd() {
  return neurov::PDController<S>(with_pd_gains<neurov::PDConfig, S>());
}

template <typename S>
neurov::PIDController<S> pid() {
  auto cfg = with_pd_gains<neurov::PIDConfig, S>();
  cfg.ki.setConstant(S(10));
  return neurov::PIDController<S>(cfg);
}

template <typename S>
neurov::SlidingModeController<S> smc() {
  neurov::SlidingModeConfig<S> cfg;
  cfg.kd.setConstant(S(100));
  cfg.k.setConstant(S(20));
  cfg.phi.setConstant(S(0.1));
  EXPECT_TRUE(neurov::regressor_parameters(neurov::nerov_parameters<S>(), cfg.theta).ok());
  return neurov::SlidingModeController<S>(cfg);
}

template <typename S>
neurov::ComputedTorqueController<S> computed_torque() {
  neurov::ComputedTorqueConfig<S> cfg;
  cfg.kd << S(200), S(200), S(200), S(50), S(50), S(50);
  cfg.vehicle = neurov::nerov_parameters<S>();
  return neurov::ComputedTorqueController<S>(cfg);
}

}  // namespace neurov_test
