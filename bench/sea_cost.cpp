// What the sea costs a run: the 600 s closed loop of bench_common.hpp (at
// 10 m depth) calm, with a Gauss-Markov current, and with waves of 200
// components (sea state 4: JONSWAP Hs 1.88 m, Tp 8.8 s) on top, driven by a
// PD controller (the plant's cost shows) and by the NN controller (N = 64).
// Prints the median wall time of each and its ratio to the calm run.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "bench_common.hpp"

namespace {

using namespace neurov;

SimulationConfig<double> config(bool current, bool waves) {
  SimulationConfig<double> c = neurov_bench::closed_loop_config<double>();
  c.eta0(2) = 10.0;
  c.command.poses.col(2).setConstant(10.0);
  if (current) {
    c.current_model = CurrentModel::gauss_markov;
    c.gauss_markov_current.direction_std = 5.0;
  }
  if (waves) {
    WaveConfig<double> w;
    w.hs = 1.88;
    w.tp = 8.8;
    w.components = 200;
    c.waves = w;
  }
  return c;
}

template <typename Make>
double median_seconds(const SimulationConfig<double>& c, Make make, int repetitions) {
  const Vehicle<double> vehicle = neurov_bench::nerov<double>();
  std::vector<double> times;
  for (int i = 0; i < repetitions; ++i) {
    auto ctl = make();
    SimulationResult<double> r;
    const auto t0 = std::chrono::steady_clock::now();
    if (simulate(vehicle, ctl, c, r)) return -1.0;
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

}  // namespace

int main() {
  const int reps = 7;
  const auto pd = [] {
    PDConfig<double> cfg;
    cfg.kp.setConstant(200);
    cfg.kd.setConstant(300);
    PDController<double> c;
    (void)PDController<double>::create(cfg, c);
    return c;
  };
  const auto nn = [] { return neurov_bench::nn_controller<double>(64); };
  std::printf("%-4s %-28s %12s %8s\n", "ctl", "sea", "median [ms]", "ratio");
  const char* names[3] = {"calm", "gauss_markov current", "current + waves (200)"};
  const bool cur[3] = {false, true, true}, wav[3] = {false, false, true};
  for (int which = 0; which < 2; ++which) {
    double calm = 0.0;
    for (int s = 0; s < 3; ++s) {
      const SimulationConfig<double> c = config(cur[s], wav[s]);
      const double t = which == 0 ? median_seconds(c, pd, reps) : median_seconds(c, nn, reps);
      if (s == 0) calm = t;
      std::printf("%-4s %-28s %12.2f %8.2f\n", which == 0 ? "PD" : "NN", names[s], 1e3 * t,
                  t / calm);
    }
  }
  return 0;
}
