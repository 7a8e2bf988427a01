// Google Benchmark suite of neurov's real-time path, in double and float:
// kinematics, the plant, one RK4 step, the RBF basis, the NN controller step
// over N = 16 ... 4096 centres, the linearly parameterised step and whole
// closed-loop runs (single-threaded, and a batch over 1 and 2 threads).
//
//   neurov_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// Every benchmark steps through a ring of inputs (bench_common.hpp) so that
// nothing is timed on one constant input.
#include <benchmark/benchmark.h>

#include <atomic>
#include <thread>
#include <vector>

#include "bench_ring.hpp"
#include "neurov/sim/batch.hpp"

namespace {

using neurov_bench::StepInput;
using neurov_bench::V6;

using neurov_bench::kRing;
using neurov_bench::over_ring;
using neurov_bench::ring;

/// A thrust the plant benchmarks apply, the same at every step.
template <typename S>
V6<S> tau_applied() {
  return (V6<S>() << S(100), S(20), S(-30), S(2), S(-3), S(5)).finished();
}

// ---------------------------------------------------------------- kinematics

/// A kinematic matrix (J, J^-1 or J_dot) written by kin(x, m) from the ring's
/// inputs.
template <typename S, typename Kin>
void time_kinematics(benchmark::State& state, Kin kin) {
  neurov::Matrix6<S> m;
  over_ring<S>(state, [&](const StepInput<S>& x) {
    benchmark::DoNotOptimize(kin(x, m));
    benchmark::DoNotOptimize(m.data());
  });
}

template <typename S>
void BM_Jacobian(benchmark::State& state) {
  time_kinematics<S>(state, [](const StepInput<S>& x, neurov::Matrix6<S>& m) {
    return neurov::jacobian(x.eta, m);
  });
}

template <typename S>
void BM_JacobianInverse(benchmark::State& state) {
  time_kinematics<S>(state, [](const StepInput<S>& x, neurov::Matrix6<S>& m) {
    return neurov::jacobian_inverse(x.eta, m);
  });
}

template <typename S>
void BM_JacobianDot(benchmark::State& state) {
  time_kinematics<S>(state, [](const StepInput<S>& x, neurov::Matrix6<S>& m) {
    return neurov::jacobian_dot(x.eta, x.nu, m);
  });
}

// --------------------------------------------------------------------- plant

template <typename S>
void BM_Coriolis(benchmark::State& state) {
  const auto vehicle = neurov_bench::nerov<S>();
  over_ring<S>(state, [&](const StepInput<S>& x) {
    neurov::Matrix6<S> c = vehicle.coriolis(x.nu);
    benchmark::DoNotOptimize(c.data());
  });
}

/// C(nu) nu without forming C: what the plant uses.
template <typename S>
void BM_CoriolisForce(benchmark::State& state) {
  const auto vehicle = neurov_bench::nerov<S>();
  over_ring<S>(state, [&](const StepInput<S>& x) {
    V6<S> f = vehicle.coriolis_force(x.nu);
    benchmark::DoNotOptimize(f.data());
  });
}

template <typename S>
void BM_Acceleration(benchmark::State& state) {
  const auto vehicle = neurov_bench::nerov<S>();
  const V6<S> tau = tau_applied<S>();
  V6<S> nu_dot;
  over_ring<S>(state, [&](const StepInput<S>& x) {
    benchmark::DoNotOptimize(vehicle.acceleration(x.eta, x.nu, tau, nu_dot));
    benchmark::DoNotOptimize(nu_dot.data());
  });
}

template <typename S>
void BM_Rk4Step(benchmark::State& state) {
  const auto vehicle = neurov_bench::nerov<S>();
  const V6<S> tau = tau_applied<S>();
  over_ring<S>(state, [&](const StepInput<S>& x) {
    V6<S> eta = x.eta, nu = x.nu;
    benchmark::DoNotOptimize(neurov::rk4_step(vehicle, eta, nu, tau, S(0.02)));
    benchmark::DoNotOptimize(eta.data());
    benchmark::DoNotOptimize(nu.data());
  });
}

/// The batch's plant kernel alone (model/plant_block.hpp): one RK4 step of
/// a full block of NEROV lanes, states from the same ring as BM_Rk4Step;
/// ns_per_lane_step is the time per lane, beside BM_Rk4Step's single run.
template <typename S>
void BM_PlantBlock(benchmark::State& state) {
  const auto vehicle = neurov_bench::nerov<S>();
  const V6<S> tau = tau_applied<S>();
  neurov::PlantBlock<S> block;
  block.lanes = neurov::kPlantBlockWidth;
  for (int j = 0; j < block.lanes; ++j) {
    for (int f = 0; f < neurov::detail::plant_coef::count; ++f)
      block.coefficients[f][j] = vehicle.plant_coefficients()[f];
    for (int i = 0; i < 6; ++i) block.tau[i][j] = tau(i);
    for (int i = 0; i < 3; ++i) block.current[i][j] = S(0);
    block.h[j] = S(0.02);
  }
  int lane = 0;
  over_ring<S>(state, [&](const StepInput<S>& x) {
    // One new state a call, as BM_Rk4Step takes: each lane restarts from
    // the ring in turn, so the states stay on the ring's trajectories.
    for (int i = 0; i < 6; ++i) {
      block.eta[i][lane] = x.eta(i);
      block.nu[i][lane] = x.nu(i);
    }
    lane = (lane + 1) % block.lanes;
    neurov::plant_rk4_block(block);
    benchmark::DoNotOptimize(block.eta);
  });
  state.counters["ns_per_lane_step"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * neurov::kPlantBlockWidth,
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// --------------------------------------------------------------- controllers

template <typename S>
typename neurov::NNAdaptiveController<S>::InputVector network_input(const StepInput<S>& x) {
  neurov::TrackingError<S> e;
  const V6<S> lambda = V6<S>::Constant(S(0.5));
  (void)neurov::compute_tracking_error(x.eta, x.nu, x.eta_d, x.eta_d_dot, x.eta_d_ddot, lambda, e);
  typename neurov::NNAdaptiveController<S>::InputVector v;
  v << e.nu_r_dot, e.nu_r, x.nu, x.eta;
  return v;
}

/// g(x) alone: 24-input distances to N centres and N exponentials.
template <typename S>
void BM_RbfBasis(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto net = neurov_bench::network<S>(n);
  std::vector<typename neurov::NNAdaptiveController<S>::InputVector> xs;
  for (const auto& x : ring<S>()) xs.push_back(network_input(x));
  typename neurov::NNAdaptiveController<S>::BasisVector g(n);
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(net.basis(xs[k++ % kRing], g));
    benchmark::DoNotOptimize(g.data());
    benchmark::ClobberMemory();
  }
  state.counters["N"] = n;
}

/// Steps ctl through the ring: a controller's whole step.
template <typename S, typename Ctl>
void time_steps(benchmark::State& state, Ctl& ctl) {
  V6<S> tau;
  over_ring<S>(state, [&](const StepInput<S>& x) {
    benchmark::DoNotOptimize(ctl.step(x.eta, x.nu, x.eta_d, x.eta_d_dot, x.eta_d_ddot, tau));
    benchmark::DoNotOptimize(tau.data());
  });
}

/// The whole NN step: tracking error, basis, output and weight update.
template <typename S>
void BM_NNStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  auto ctl = neurov_bench::nn_controller<S>(n);
  time_steps<S>(state, ctl);
  state.counters["N"] = n;
}

/// The step with the centre count fixed at compile time (firmware's choice).
template <typename S, int N>
void BM_NNStepFixed(benchmark::State& state) {
  auto ctl = neurov_bench::nn_controller<S, N>(N);
  time_steps<S>(state, ctl);
  state.counters["N"] = N;
}

template <typename S>
void BM_LinearAdaptiveStep(benchmark::State& state) {
  auto ctl = neurov_bench::linear_controller<S>();
  time_steps<S>(state, ctl);
}

/// The tracking error every controller computes first (J, J^-1, J_dot terms).
template <typename S>
void BM_TrackingError(benchmark::State& state) {
  const V6<S> lambda = V6<S>::Constant(S(0.5));
  neurov::TrackingError<S> e;
  over_ring<S>(state, [&](const StepInput<S>& x) {
    benchmark::DoNotOptimize(
        neurov::compute_tracking_error(x.eta, x.nu, x.eta_d, x.eta_d_dot, x.eta_d_ddot, lambda, e));
    benchmark::DoNotOptimize(&e);
  });
}

// ---------------------------------------------------------------- closed loop

/// 600 s of the paper's loop (N = 64, 5 Hz, 10 RK4 substeps, no thrusters).
/// real_time_factor = simulated seconds per second of CPU.
template <typename S>
void BM_ClosedLoop(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto vehicle = neurov_bench::nerov<S>();
  const auto config = neurov_bench::closed_loop_config<S>();
  auto ctl = neurov_bench::nn_controller<S>(n);
  neurov::SimulationResult<S> result;
  for (auto _ : state) {
    ctl.reset();
    benchmark::DoNotOptimize(neurov::simulate(vehicle, ctl, config, result));
    benchmark::DoNotOptimize(result.eta.data());
    benchmark::ClobberMemory();
  }
  state.counters["N"] = n;
  state.counters["real_time_factor"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(config.duration),
                         benchmark::Counter::kIsRate);
}

/// The plant alone over the same 600 s (3000 x 10 RK4 steps), for the split.
template <typename S>
void BM_ClosedLoopPlantOnly(benchmark::State& state) {
  const auto vehicle = neurov_bench::nerov<S>();
  const auto& in = ring<S>();
  const V6<S> tau = tau_applied<S>();
  for (auto _ : state) {
    V6<S> eta = in[0].eta, nu = in[0].nu;
    for (int k = 0; k < 3000 * 10; ++k) {
      const V6<S> t = (k & 1) ? tau : V6<S>(-tau);
      benchmark::DoNotOptimize(neurov::rk4_step(vehicle, eta, nu, t, S(0.02)));
    }
    benchmark::DoNotOptimize(eta.data());
    benchmark::ClobberMemory();
  }
}

/// Monte-Carlo batch: `runs` independent closed loops with perturbed mass and
/// damping and shifted start poses, spread over state.range(1) threads.
/// runs_per_second is per wall-clock second.
void BM_ClosedLoopBatch(benchmark::State& state) {
  using S = double;
  const int runs = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  std::vector<neurov::Vehicle<S>> vehicles(static_cast<std::size_t>(runs));
  std::vector<neurov::SimulationConfig<S>> configs(static_cast<std::size_t>(runs));
  neurov_bench::Uniform u(99);
  for (int r = 0; r < runs; ++r) {
    auto p = neurov::nerov_parameters<S>();
    p.mass *= u(0.9, 1.1);
    p.linear_damping *= u(0.8, 1.2);
    p.quadratic_damping *= u(0.8, 1.2);
    (void)neurov::Vehicle<S>::create(p, vehicles[static_cast<std::size_t>(r)]);
    auto& c = configs[static_cast<std::size_t>(r)];
    c = neurov_bench::closed_loop_config<S>();
    c.eta0(0) = u(-1, 1);
    c.eta0(1) = u(-1, 1);
    c.seed = static_cast<std::uint64_t>(r);
    c.noise_eta = V6<S>::Constant(0.01);
    c.noise_nu = V6<S>::Constant(0.005);
  }
  const auto prototype = neurov_bench::nn_controller<S>(64);
  for (auto _ : state) {
    std::atomic<int> next{0};
    auto worker = [&] {
      auto ctl = prototype;
      neurov::SimulationResult<S> result;
      for (int r; (r = next.fetch_add(1)) < runs;) {
        ctl.reset();
        (void)neurov::simulate(vehicles[static_cast<std::size_t>(r)], ctl,
                               configs[static_cast<std::size_t>(r)], result);
        benchmark::DoNotOptimize(result.eta.data());
      }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
  }
  state.counters["threads"] = threads;
  state.counters["runs_per_second"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * runs, benchmark::Counter::kIsRate);
}

/// One control period of K lanes of the batch (BatchSimulator::step, one
/// thread): NEROV on the paper's path, 10 RK4 substeps, no thrusters, a
/// fixed force; a lane whose run ends starts again (untimed). The plant
/// per lane-step, double against float; env_steps_per_second is per second
/// of CPU.
template <typename S>
void BM_BatchStep(benchmark::State& state) {
  const auto k = static_cast<std::size_t>(state.range(0));
  const std::vector<neurov::Vehicle<S>> vehicles(k, neurov_bench::nerov<S>());
  const std::vector<neurov::SimulationConfig<S>> configs(k, neurov_bench::closed_loop_config<S>());
  neurov::BatchSimulator<S> batch;
  if (neurov::BatchSimulator<S>::create(vehicles, configs, batch)) {
    state.SkipWithError("the batch was refused");
    return;
  }
  std::vector<S> tau(6 * k);
  for (std::size_t i = 0; i < tau.size(); ++i) tau[i] = S(i % 6 < 3 ? 20 : 2);
  std::vector<std::uint8_t> statuses(k);
  for (auto _ : state) {
    batch.step(tau.data(), nullptr, statuses.data());
    if (batch.lane(0).done()) {
      state.PauseTiming();
      for (std::size_t i = 0; i < k; ++i) batch.reset(i, i);
      state.ResumeTiming();
    }
    benchmark::DoNotOptimize(statuses.data());
  }
  state.counters["env_steps_per_second"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(k),
                         benchmark::Counter::kIsRate);
}

// ---------------------------------------------------------------- machine

/// The core's clock while it runs code: a chain of dependent integer adds
/// retires one add per cycle on every x86-64 core of the last decade, so
/// adds per second is cycles per second. Used to turn the NN step's counted
/// operations into a lower bound in nanoseconds (bench/README.md).
void BM_CoreClock(benchmark::State& state) {
  constexpr long kAdds = 1L << 20;
  for (auto _ : state) {
    unsigned long x = 0;
    for (long i = 0; i < kAdds; ++i) {
      x += static_cast<unsigned long>(i);
      // An empty asm that claims to read and write x: the compiler can
      // neither fold the chain nor vectorise it, and emits no instruction.
      asm volatile("" : "+r"(x));
    }
    benchmark::DoNotOptimize(x);
  }
  state.counters["GHz"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * kAdds * 1e-9, benchmark::Counter::kIsRate);
}

void centre_counts(benchmark::internal::Benchmark* b) {
  for (int n : {16, 64, 256, 1024, 4096}) b->Arg(n);
}

}  // namespace

BENCHMARK_TEMPLATE(BM_Jacobian, double);
BENCHMARK_TEMPLATE(BM_Jacobian, float);
BENCHMARK_TEMPLATE(BM_JacobianInverse, double);
BENCHMARK_TEMPLATE(BM_JacobianInverse, float);
BENCHMARK_TEMPLATE(BM_JacobianDot, double);
BENCHMARK_TEMPLATE(BM_JacobianDot, float);
BENCHMARK_TEMPLATE(BM_Coriolis, double);
BENCHMARK_TEMPLATE(BM_Coriolis, float);
BENCHMARK_TEMPLATE(BM_CoriolisForce, double);
BENCHMARK_TEMPLATE(BM_CoriolisForce, float);
BENCHMARK_TEMPLATE(BM_Acceleration, double);
BENCHMARK_TEMPLATE(BM_Acceleration, float);
BENCHMARK_TEMPLATE(BM_Rk4Step, double);
BENCHMARK_TEMPLATE(BM_Rk4Step, float);
BENCHMARK_TEMPLATE(BM_PlantBlock, double);
BENCHMARK_TEMPLATE(BM_PlantBlock, float);
BENCHMARK_TEMPLATE(BM_TrackingError, double);
BENCHMARK_TEMPLATE(BM_TrackingError, float);
BENCHMARK_TEMPLATE(BM_RbfBasis, double)->Apply(centre_counts);
BENCHMARK_TEMPLATE(BM_RbfBasis, float)->Apply(centre_counts);
BENCHMARK_TEMPLATE(BM_NNStep, double)->Apply(centre_counts);
BENCHMARK_TEMPLATE(BM_NNStep, float)->Apply(centre_counts);
BENCHMARK_TEMPLATE(BM_NNStepFixed, double, 64);
BENCHMARK_TEMPLATE(BM_NNStepFixed, double, 256);
BENCHMARK_TEMPLATE(BM_NNStepFixed, float, 64);
BENCHMARK_TEMPLATE(BM_NNStepFixed, float, 256);
BENCHMARK_TEMPLATE(BM_LinearAdaptiveStep, double);
BENCHMARK_TEMPLATE(BM_LinearAdaptiveStep, float);
BENCHMARK_TEMPLATE(BM_ClosedLoop, double)->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_ClosedLoop, float)->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_ClosedLoopPlantOnly, double)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClosedLoopBatch)
    ->Args({200, 1})
    ->Args({200, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

BENCHMARK_TEMPLATE(BM_BatchStep, double)->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_BatchStep, float)->Arg(256)->Unit(benchmark::kMicrosecond);

BENCHMARK(BM_CoreClock);

BENCHMARK_MAIN();
