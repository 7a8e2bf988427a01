// Worst-case latency of the NN controller step, as a firmware engineer reads
// it: 10^6 consecutive steps, each timed on its own, then the median, p99,
// p99.9 and maximum; plus sizeof the controller and the heap it owns.
//
//   neurov_latency [--steps 1000000] [--cpu 1] [--json out.json]
//
// Each step is timed with the time-stamp counter (x86-64; calibrated against
// steady_clock) or steady_clock elsewhere; the cost of the timer itself is
// measured the same way and printed, not subtracted. On a shared machine the
// tail (p99.9, max) includes preemption by other processes: pin to a CPU
// (--cpu) and run on a quiet machine to see the code's own tail.
#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#if defined(__x86_64__) || defined(_M_X64)
#include <x86intrin.h>
#define NEUROV_BENCH_TSC 1
#else
#define NEUROV_BENCH_TSC 0
#endif

#if defined(__linux__)
#include <malloc.h>
#include <sched.h>
#include <sys/mman.h>
#endif

#include "bench_common.hpp"

namespace {

using neurov_bench::StepInput;
using neurov_bench::V6;

inline std::uint64_t ticks() noexcept {
#if NEUROV_BENCH_TSC
  // lfence keeps the counter read from moving across the timed code.
  _mm_lfence();
  const std::uint64_t t = __rdtsc();
  _mm_lfence();
  return t;
#else
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(
          std::chrono::steady_clock::now().time_since_epoch())
          .count());
#endif
}

/// Nanoseconds per tick.
double calibrate() {
#if NEUROV_BENCH_TSC
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const std::uint64_t c0 = ticks();
  while (clock::now() - t0 < std::chrono::milliseconds(200)) {
  }
  const std::uint64_t c1 = ticks();
  const double ns = std::chrono::duration<double, std::nano>(clock::now() - t0).count();
  return ns / static_cast<double>(c1 - c0);
#else
  return 1.0;
#endif
}

struct Summary {
  double median, p99, p999, max, mean;
};

Summary summarise(std::vector<std::uint64_t>& t, double ns_per_tick) {
  std::vector<std::uint64_t> s = t;
  std::sort(s.begin(), s.end());
  auto q = [&](double p) {
    const std::size_t i = static_cast<std::size_t>(std::ceil(p * static_cast<double>(s.size()))) - 1;
    return static_cast<double>(s[std::min(i, s.size() - 1)]) * ns_per_tick;
  };
  double sum = 0;
  for (auto v : s) sum += static_cast<double>(v);
  return {q(0.5), q(0.99), q(0.999), static_cast<double>(s.back()) * ns_per_tick,
          sum / static_cast<double>(s.size()) * ns_per_tick};
}

/// Heap bytes a copy of `x` owns (glibc's accounting, so including malloc's
/// per-block overhead): the copy lives on the stack, so only what it
/// allocates itself is counted; 0 for a controller with a compile-time N.
template <typename T>
long heap_bytes_of(const T& x) {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const auto before = mallinfo2().uordblks;
  std::optional<T> copy(x);
  // The copy must exist where the compiler cannot see it unused.
  asm volatile("" : : "r"(&*copy) : "memory");
  const auto after = mallinfo2().uordblks;
  return static_cast<long>(after) - static_cast<long>(before);
#else
  (void)x;
  return -1;
#endif
}

struct Row {
  std::string name;
  int n;
  Summary s;
  std::size_t size_of;
  long heap;
};

template <typename Ctl>
Row measure(const char* name, Ctl ctl, int n, long steps, double ns_per_tick) {
  using S = typename Ctl::Scalar;
  const auto inputs = neurov_bench::step_inputs<S>(1024);
  std::vector<std::uint64_t> t(static_cast<std::size_t>(steps));
  V6<S> tau;
  // Warm caches, branch predictors and the CPU's clock before measuring.
  for (long k = 0; k < 20000; ++k) {
    const auto& x = inputs[static_cast<std::size_t>(k) & 1023];
    (void)ctl.step(x.eta, x.nu, x.eta_d, x.eta_d_dot, x.eta_d_ddot, tau);
  }
  for (long k = 0; k < steps; ++k) {
    const auto& x = inputs[static_cast<std::size_t>(k) & 1023];
    const std::uint64_t a = ticks();
    (void)ctl.step(x.eta, x.nu, x.eta_d, x.eta_d_dot, x.eta_d_ddot, tau);
    const std::uint64_t b = ticks();
    t[static_cast<std::size_t>(k)] = b - a;
  }
  if (!tau.allFinite()) std::fprintf(stderr, "warning: non-finite tau\n");
  return {name, n, summarise(t, ns_per_tick), sizeof(Ctl), heap_bytes_of(ctl)};
}

Summary timer_overhead(long steps, double ns_per_tick) {
  std::vector<std::uint64_t> t(static_cast<std::size_t>(steps));
  for (long k = 0; k < steps; ++k) {
    const std::uint64_t a = ticks();
    const std::uint64_t b = ticks();
    t[static_cast<std::size_t>(k)] = b - a;
  }
  return summarise(t, ns_per_tick);
}

}  // namespace

int main(int argc, char** argv) {
  long steps = 1000000;
  int cpu = -1;
  const char* json = nullptr;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) {
      steps = std::atol(argv[++i]);
    } else if (!std::strcmp(argv[i], "--cpu") && i + 1 < argc) {
      cpu = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--json") && i + 1 < argc) {
      json = argv[++i];
    } else {
      std::fprintf(stderr, "usage: %s [--steps N] [--cpu K] [--json FILE]\n", argv[0]);
      return 2;
    }
  }
  if (steps < 1000) steps = 1000;
#if defined(__linux__)
  if (cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    if (sched_setaffinity(0, sizeof set, &set) != 0) std::perror("sched_setaffinity");
  }
  // No page faults in the timed loop (best effort: needs the privilege).
  (void)mlockall(MCL_CURRENT | MCL_FUTURE);
#endif
  const double ns_per_tick = calibrate();

  std::vector<Row> rows;
  for (int n : {64, 256}) {
    rows.push_back(measure("double", neurov_bench::nn_controller<double>(n), n, steps, ns_per_tick));
  }
  rows.push_back(
      measure("double fixed N", neurov_bench::nn_controller<double, 64>(64), 64, steps, ns_per_tick));
  rows.push_back(measure("double fixed N", neurov_bench::nn_controller<double, 256>(256), 256, steps,
                         ns_per_tick));
  for (int n : {64, 256}) {
    rows.push_back(measure("float", neurov_bench::nn_controller<float>(n), n, steps, ns_per_tick));
  }
  rows.push_back(
      measure("float fixed N", neurov_bench::nn_controller<float, 256>(256), 256, steps, ns_per_tick));
  const Summary overhead = timer_overhead(steps, ns_per_tick);

  std::printf("NN controller step, %ld consecutive steps each, 24 inputs, times in ns%s\n", steps,
              NEUROV_BENCH_TSC ? " (TSC)" : " (steady_clock)");
  std::printf("%-16s %5s %9s %9s %9s %9s %9s %9s %12s %10s\n", "scalar", "N", "median", "mean",
              "p99", "p99.9", "max", "p99.9/med", "sizeof [B]", "heap [B]");
  for (const auto& r : rows)
    std::printf("%-16s %5d %9.1f %9.1f %9.1f %9.1f %9.0f %9.2f %12zu %10ld\n", r.name.c_str(), r.n,
                r.s.median, r.s.mean, r.s.p99, r.s.p999, r.s.max, r.s.p999 / r.s.median, r.size_of,
                r.heap);
  std::printf("timer overhead (two reads, included above): median %.1f ns, p99.9 %.1f ns\n",
              overhead.median, overhead.p999);

  if (json) {
    if (FILE* f = std::fopen(json, "w")) {
      std::fprintf(f, "{\n  \"steps\": %ld,\n  \"timer_overhead_ns\": %.2f,\n  \"rows\": [\n", steps,
                   overhead.median);
      for (std::size_t i = 0; i < rows.size(); ++i) {
        const auto& r = rows[i];
        std::fprintf(f,
                     "    {\"scalar\": \"%s\", \"N\": %d, \"median_ns\": %.2f, \"mean_ns\": %.2f, "
                     "\"p99_ns\": %.2f, \"p999_ns\": %.2f, \"max_ns\": %.1f, \"sizeof\": %zu, "
                     "\"heap_bytes\": %ld}%s\n",
                     r.name.c_str(), r.n, r.s.median, r.s.mean, r.s.p99, r.s.p999, r.s.max, r.size_of,
                     r.heap, i + 1 < rows.size() ? "," : "");
      }
      std::fprintf(f, "  ]\n}\n");
      std::fclose(f);
    }
  }
  return 0;
}
