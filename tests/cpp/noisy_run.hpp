// A short noisy run shared by the batch tests: a 2 s ramp to a pose off the
// origin, measured with noise, so lanes that differ only by their seed differ.
#pragma once

#include <cstdint>

#include "neurov/sim/config.hpp"

namespace neurov_test {

inline neurov::SimulationConfig<double> noisy_run(std::uint64_t seed, double nu_noise = 0.005) {
  neurov::SimulationConfig<double> c;
  c.duration = 2.0;
  c.command.times.resize(2);
  c.command.times << 0, 2;
  c.command.poses.setZero(2, 6);
  c.command.poses.row(1) << 1, 0, 0.5, 0, 0, 0.3;
  c.noise_eta.setConstant(0.01);
  c.noise_nu.setConstant(nu_noise);
  c.seed = seed;
  return c;
}

}  // namespace neurov_test
