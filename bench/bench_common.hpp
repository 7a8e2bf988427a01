// Inputs shared by the benchmarks: the paper's vehicle and controller
// settings, a ring of realistic states to step through, and the closed-loop
// scenario that bench/compare.py also runs (NEROV, NN with N centres, 600 s at
// 5 Hz, 10 RK4 substeps, no thrusters).
//
// Inputs come from a seeded generator and are cycled through, so no benchmark
// times a computation the optimiser could fold, or a branch predictor could
// learn from one repeated input.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "neurov/neurov.hpp"

namespace neurov_bench {

/// Deterministic uniform numbers (splitmix64), the same on every platform.
class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : state_(seed) {}
  double operator()(double lo, double hi) {
    state_ += 0x9E3779B97F4A7C15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return lo + (hi - lo) * (static_cast<double>(z >> 11) * 0x1.0p-53);
  }

 private:
  std::uint64_t state_;
};

template <typename S>
using V6 = neurov::Vector6<S>;

/// One controller input: the measured state and the desired trajectory.
template <typename S>
struct StepInput {
  V6<S> eta, nu, eta_d, eta_d_dot, eta_d_ddot;
};

/// States near a slowly moving reference, as a tracking controller sees them.
template <typename S>
std::vector<StepInput<S>> step_inputs(int count, std::uint64_t seed = 7) {
  Uniform u(seed);
  std::vector<StepInput<S>> out(static_cast<std::size_t>(count));
  for (auto& in : out) {
    for (int i = 0; i < 6; ++i) {
      const bool angle = i >= 3;
      in.eta(i) = static_cast<S>(angle ? u(-0.4, 0.4) : u(-10.0, 10.0));
      in.nu(i) = static_cast<S>(angle ? u(-0.2, 0.2) : u(-0.5, 0.5));
      in.eta_d(i) = in.eta(i) + static_cast<S>(angle ? u(-0.05, 0.05) : u(-0.5, 0.5));
      in.eta_d_dot(i) = static_cast<S>(angle ? u(-0.1, 0.1) : u(-0.3, 0.3));
      in.eta_d_ddot(i) = static_cast<S>(u(-0.05, 0.05));
    }
  }
  return out;
}

/// The box the Python package fills with centres by default (simulation.py,
/// default_centre_box) around the bench's states.
template <typename S>
Eigen::Matrix<S, Eigen::Dynamic, neurov::kNNInputs> centres(int n, std::uint64_t seed = 1) {
  Uniform u(seed);
  Eigen::Matrix<S, Eigen::Dynamic, neurov::kNNInputs> c(n, neurov::kNNInputs);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < neurov::kNNInputs; ++i) {
      const int block = i / 6, dof = i % 6;
      double half = 0.5;                        // nu_r_dot
      if (block == 1 || block == 2) half = dof < 3 ? 1.0 : 0.5;  // nu_r, nu
      if (block == 3) half = dof < 3 ? 12.0 : 0.9;             // eta
      c(j, i) = static_cast<S>(u(-half, half));
    }
  return c;
}

/// The paper's network: N centres, width 30, zero weights.
template <typename S, int N = Eigen::Dynamic>
typename neurov::NNAdaptiveController<S, N>::Network network(int n) {
  using Net = typename neurov::NNAdaptiveController<S, N>::Network;
  Net net;
  const typename Net::CentreMatrix c = centres<S>(n);
  const typename Net::BasisVector w = Net::BasisVector::Constant(n, S(30));
  (void)Net::create(c, w, net);
  return net;
}

/// A controller configuration at the paper's 5 Hz with the K_d and Lambda of
/// the project's Fig. 3 scenario.
template <template <typename> class Config, typename S>
Config<S> fig3_gains() {
  Config<S> c;
  c.lambda = V6<S>::Constant(S(0.5));
  c.kd << S(200), S(200), S(200), S(50), S(50), S(50);
  c.dt = S(0.2);
  return c;
}

/// The paper's controller settings: gamma 0.3 on the Fig. 3 gains.
template <typename S>
neurov::NNAdaptiveConfig<S> nn_config() {
  auto c = fig3_gains<neurov::NNAdaptiveConfig, S>();
  c.gamma = S(0.3);
  return c;
}

template <typename S, int N = Eigen::Dynamic>
neurov::NNAdaptiveController<S, N> nn_controller(int n) {
  neurov::NNAdaptiveController<S, N> ctl;
  (void)neurov::NNAdaptiveController<S, N>::create(network<S, N>(n), nn_config<S>(), ctl);
  return ctl;
}

template <typename S>
neurov::LinearAdaptiveController<S> linear_controller() {
  auto c = fig3_gains<neurov::LinearAdaptiveConfig, S>();
  c.gamma = neurov::ParameterVector<S>::Constant(S(1));
  neurov::LinearAdaptiveController<S> ctl;
  (void)neurov::LinearAdaptiveController<S>::create(c, ctl);
  return ctl;
}

template <typename S>
neurov::Vehicle<S> nerov() {
  neurov::Vehicle<S> v;
  (void)neurov::Vehicle<S>::create(neurov::nerov_parameters<S>(), v);
  return v;
}

/// A 10 m square at 2 m depth with the heading along each leg, repeated for
/// 600 s: the closed loop that compare.py runs in neurov and in numpy.
template <typename S>
neurov::SimulationConfig<S> closed_loop_config(S duration = S(600)) {
  neurov::SimulationConfig<S> c;
  c.dt = S(0.2);
  c.substeps = 10;
  c.duration = duration;
  const double corners[4][2] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  const double headings[4] = {0.0, 1.5707963267948966, 3.141592653589793, 4.71238898038469};
  const int laps = 4, legs = 4 * laps;
  c.command.times.resize(legs + 1);
  c.command.poses.resize(legs + 1, 6);
  for (int k = 0; k <= legs; ++k) {
    // Leg k starts at corner k % 4 facing along itself; the last pose keeps
    // the last leg's heading. Headings are unwrapped over the laps.
    const int leg = k < legs ? k : legs - 1;
    c.command.times(k) = static_cast<S>(5.0 + 36.0 * k);
    c.command.poses.row(k) << static_cast<S>(corners[k % 4][0]), static_cast<S>(corners[k % 4][1]),
        S(2), S(0), S(0), static_cast<S>(headings[leg % 4] + 6.283185307179586 * (leg / 4));
  }
  return c;
}

}  // namespace neurov_bench
