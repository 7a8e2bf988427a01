// What the sea costs a run: the 600 s closed loop of bench_common.hpp (at
// 10 m depth) calm, with a Gauss-Markov current, and with waves of 200
// components (sea state 4: JONSWAP Hs 1.88 m, Tp 8.8 s) on top, driven by a
// PD controller (the plant's cost shows) and by the NN controller (N = 64).
// Prints the median and the fastest processor time of each (std::clock:
// on a shared machine the time the run was switched out does not count)
// and their ratios to the calm run.
#include <algorithm>
#include <ctime>
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
double run_seconds(const SimulationConfig<double>& c, Make make) {
  const Vehicle<double> vehicle = neurov_bench::nerov<double>();
  auto ctl = make();
  SimulationResult<double> r;
  const std::clock_t t0 = std::clock();
  if (simulate(vehicle, ctl, c, r)) return -1.0;
  return static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC;
}

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  return x[x.size() / 2];
}

}  // namespace

// The three seas are run in turn within each repetition, so that the load
// of a shared machine falls on them alike; the ratio to calm is given as
// the median over the repetitions of each repetition's ratio, and as the
// ratio of the fastest runs (the least disturbed by other work).
int main() {
  const int reps = 15;
  const auto pd = [] {
    PDConfig<double> cfg;
    cfg.kp.setConstant(200);
    cfg.kd.setConstant(300);
    PDController<double> c;
    (void)PDController<double>::create(cfg, c);
    return c;
  };
  const auto nn = [] { return neurov_bench::nn_controller<double>(64); };
  std::printf("%-4s %-24s %12s %10s %12s %10s\n", "ctl", "sea", "median [ms]", "ratio",
              "fastest [ms]", "ratio");
  const char* names[3] = {"calm", "gauss_markov current", "current + waves (200)"};
  const bool cur[3] = {false, true, true}, wav[3] = {false, false, true};
  for (int which = 0; which < 2; ++which) {
    std::vector<double> times[3], ratios[3];
    for (int i = 0; i < reps; ++i) {
      double t[3];
      for (int s = 0; s < 3; ++s) {
        const SimulationConfig<double> c = config(cur[s], wav[s]);
        t[s] = which == 0 ? run_seconds(c, pd) : run_seconds(c, nn);
        times[s].push_back(t[s]);
        ratios[s].push_back(t[s] / t[0]);
      }
    }
    const double calm_fastest = *std::min_element(times[0].begin(), times[0].end());
    for (int s = 0; s < 3; ++s) {
      const double fastest = *std::min_element(times[s].begin(), times[s].end());
      std::printf("%-4s %-24s %12.2f %10.2f %12.2f %10.2f\n", which == 0 ? "PD" : "NN", names[s],
                  1e3 * median(times[s]), median(ratios[s]), 1e3 * fastest,
                  fastest / calm_fastest);
    }
  }
  return 0;
}
