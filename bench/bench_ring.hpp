// The ring of seeded controller inputs (bench_common.hpp) that the Google
// Benchmark programs step through, shared by bench_core.cpp and
// bench_floor.cpp.
#pragma once

#include <benchmark/benchmark.h>

#include <cstddef>
#include <vector>

#include "bench_common.hpp"

namespace neurov_bench {

constexpr int kRing = 256;  // inputs cycled through; a power of two

template <typename S>
const std::vector<StepInput<S>>& ring() {
  static const std::vector<StepInput<S>> r = step_inputs<S>(kRing);
  return r;
}

/// Times f on the inputs of the ring in turn; f
/// keeps what it computes alive with benchmark::DoNotOptimize.
template <typename S, typename F>
void over_ring(benchmark::State& state, F&& f) {
  const auto& in = ring<S>();
  std::size_t k = 0;
  for (auto _ : state) {
    f(in[k++ % kRing]);
    benchmark::ClobberMemory();
  }
}

}  // namespace neurov_bench
