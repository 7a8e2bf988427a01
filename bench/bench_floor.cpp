// How far the NN step is from its floor, measured in one run: the machine's
// peak rates (independent FMA, add, load and store streams at scalar, 128,
// 256 and 512 bits, and the RBF kernels' own exp), the NN step and the
// tracking error at N = 64, 256 and 1024, then a lower bound for each step
// from the operation counts below and the peaks of the same run, printed
// with measured / bound. The derivation: bench/README.md, "The floor".
//
//   neurov_floor --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// Widths the CPU lacks (AVX2+FMA, AVX-512) are skipped, not run.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstring>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "bench_ring.hpp"

namespace {

using neurov::detail::Vec;
using neurov_bench::StepInput;
using neurov_bench::V6;

// ------------------------------------------------------- per-centre counts
//
// Per centre and per SIMD lane (bench/README.md derives them from
// rbf_kernel_loops.hpp and nn_controller.hpp): the operations of one NN step that
// the algorithm needs, not those a particular loop happens to issue.
struct CentreCounts {
  double fma;     ///< multiplies and multiply-adds (the FMA pipes)
  double add;     ///< adds, subtracts, min/max, compares, selects
  double loads;   ///< numbers read
  double stores;  ///< numbers written
  double exps;
};

template <typename S>
constexpr CentreCounts centre_counts() {
  // distance: 24 subtractions, 24 multiply-adds; 1 multiply by -1/(2 sigma^2);
  // exp: 18 (double) or 11 (float) multiplies/multiply-adds, 2 adds, 4
  // min/max/compare/select (the 2 integer ops counted as adds);
  // output, update, norm: y += w g, w -= (gamma g) a, n += w^2 for 6 rows
  // with gamma g formed once: 19.
  const double exp_fma = sizeof(S) == 8 ? 18 : 11;
  return {24 + 1 + exp_fma + 19, 24 + 2 + 4 + 2,
          // centres 24, 1/(2 sigma^2), rate, W 6; stores: g, W 6
          24 + 1 + 1 + 6, 1 + 6, 1};
}

// ------------------------------------------------------------ the streams

constexpr int kStreams = 12;  // independent chains: > latency x issue rate
constexpr long kReps = 1024;  // per timed iteration

/// An empty asm that claims to change v: no instruction, but the compiler
/// can neither fold the chain nor merge the chains into wider vectors.
template <typename V>
NEUROV_ALWAYS_INLINE void opaque(V& v) noexcept {
  asm volatile("" : "+v"(v));
}

// Twelve named accumulators rather than an array: GCC keeps an array that
// is indexed lane by lane in memory, and the chains would then time the
// stack, not the pipes.
#define FLOOR_EACH(X) X(0) X(1) X(2) X(3) X(4) X(5) X(6) X(7) X(8) X(9) X(10) X(11)
static_assert(kStreams == 12, "FLOOR_EACH names kStreams accumulators");

/// The sum of the lanes of the accumulators, so that none is dead.
template <typename S, int L, typename V>
NEUROV_ALWAYS_INLINE S lane_sum(const V& v) noexcept {
  S lanes[L];
  std::memcpy(lanes, &v, sizeof lanes);
  S sum = S(0);
  for (int l = 0; l < L; ++l) sum += lanes[l];
  return sum;
}

#define FLOOR_DECLARE(k) V acc##k = V{} + S(1e-3) * S(k + 1);
#define FLOOR_SUM(k) +acc##k

/// acc = acc m + c on kStreams independent chains.
template <typename S, int L>
NEUROV_ALWAYS_INLINE S fma_body(long reps) noexcept {
  using V = Vec<S, L>;
  FLOOR_EACH(FLOOR_DECLARE)
  V m = V{} + S(0.999999), c = V{} + S(1e-7);
  opaque(m);
  opaque(c);
#define FLOOR_FMA_STEP(k) \
  acc##k = acc##k * m + c; \
  opaque(acc##k);
  for (long r = 0; r < reps; ++r) {
    FLOOR_EACH(FLOOR_FMA_STEP)
  }
  const V sum = V{} FLOOR_EACH(FLOOR_SUM);
  return lane_sum<S, L>(sum);
}

/// acc = acc + c on kStreams independent chains.
template <typename S, int L>
NEUROV_ALWAYS_INLINE S add_body(long reps) noexcept {
  using V = Vec<S, L>;
  FLOOR_EACH(FLOOR_DECLARE)
  V c = V{} + S(1e-7);
  opaque(c);
#define FLOOR_ADD_STEP(k) \
  acc##k = acc##k + c;    \
  opaque(acc##k);
  for (long r = 0; r < reps; ++r) {
    FLOOR_EACH(FLOOR_ADD_STEP)
  }
  const V sum = V{} FLOOR_EACH(FLOOR_SUM);
  return lane_sum<S, L>(sum);
}

/// Loads: a dot product of two arrays in L1 on kStreams accumulators, two
/// loads per multiply-add, so that the two FMA pipes could take four loads
/// a cycle, more than an L1 serves.
template <typename S, int L>
NEUROV_ALWAYS_INLINE S load_body(const S* a, const S* b, long n, long reps) noexcept {
  using V = Vec<S, L>;
  FLOOR_EACH(FLOOR_DECLARE)
#define FLOOR_LOAD_STEP(k)                                \
  {                                                       \
    V x, y;                                               \
    neurov::detail::load<S, L>(x, a + i + k * L);         \
    neurov::detail::load<S, L>(y, b + i + k * L);         \
    acc##k = acc##k + x * y;                              \
    opaque(acc##k);                                       \
  }
  for (long r = 0; r < reps; ++r)
    for (long i = 0; i + kStreams * L <= n; i += kStreams * L) {
      FLOOR_EACH(FLOOR_LOAD_STEP)
    }
  const V sum = V{} FLOOR_EACH(FLOOR_SUM);
  return lane_sum<S, L>(sum);
}

template <typename S, int L>
NEUROV_ALWAYS_INLINE void store_body(S* p, long n, long reps) noexcept {
  using V = Vec<S, L>;
  V v = V{} + S(1);
  opaque(v);
  for (long r = 0; r < reps; ++r)
    for (long i = 0; i + L <= n; i += L) {
      neurov::detail::store<S, L>(p + i, v);
      asm volatile("" : : "r"(p) : "memory");
    }
}

/// The kernels' exp (rbf_kernel_loops.hpp) over n numbers in L1, vector by vector
/// as the basis loop applies it.
template <typename S, int L>
NEUROV_ALWAYS_INLINE void exp_body(const S* x, S* y, long n, long reps) noexcept {
  using V = Vec<S, L>;
  for (long r = 0; r < reps; ++r) {
    for (long i = 0; i + L <= n; i += L) {
      V v;
      neurov::detail::load<S, L>(v, x + i);
      neurov::detail::exp_nonpositive<S, L>(v);
      neurov::detail::store<S, L>(y + i, v);
    }
    asm volatile("" : : "r"(y) : "memory");
  }
}

template <typename S>
NEUROV_ALWAYS_INLINE void exp_body1(const S* x, S* y, long n, long reps) noexcept {
  for (long r = 0; r < reps; ++r) {
    for (long i = 0; i < n; ++i) {
      S v = x[i];
      neurov::detail::exp_nonpositive<S, 1>(v);
      y[i] = v;
      asm volatile("" : : "r"(y) : "memory");  // keeps the loop scalar
    }
  }
}

// Widths: 0 = scalar, then 16, 32, 64 bytes. The FMA streams need the FMA
// extension (AVX2+FMA target) even at scalar and 128 bits; loads, stores,
// adds and exp at scalar and 128 bits are the build's own (SSE2) code.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define FLOOR_X86 1
#define FLOOR_FMA __attribute__((target("avx2,fma"), noinline))
#define FLOOR_AVX512 \
  __attribute__((target("avx512f,avx512vl,avx512dq,avx512bw,avx2,fma"), noinline))
#else
#define FLOOR_X86 0
#define FLOOR_FMA __attribute__((noinline))
#define FLOOR_AVX512 __attribute__((noinline))
#endif
#define FLOOR_PLAIN __attribute__((noinline))

enum class Kind { fma, add, load, store, exp, load_l2 };

bool width_supported(int bytes) {
#if FLOOR_X86
  __builtin_cpu_init();
  if (bytes == 64)
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
           __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw");
  if (bytes == 32) return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return true;
#else
  return bytes <= 16;
#endif
}

bool fma_supported() {
#if FLOOR_X86
  __builtin_cpu_init();
  return __builtin_cpu_supports("fma");
#else
  return true;
#endif
}

constexpr long kArray = 2048;  // numbers per array: 16 KB of doubles, in L1
constexpr long kL2Array = 32768;  // numbers per array: 256 KB of doubles, in L2 not L1

template <typename S>
struct Arrays {
  alignas(64) S a[kArray], b[kArray], y[kArray];
  Arrays() {
    neurov_bench::Uniform u(5);
    for (long i = 0; i < kArray; ++i) {
      a[i] = static_cast<S>(u(0.5, 1.0));
      // exp arguments as the basis sees them: -d^2 / (2 sigma^2) over [-40, 0]
      b[i] = static_cast<S>(u(-40.0, 0.0));
      y[i] = S(0);
    }
  }
};

// One function per (kind, scalar, width): a target attribute applies to a
// whole function, so the loop bodies above are inlined into these.
#define FLOOR_KERNELS(ATTR, SUFFIX, S, L)                                                   \
  ATTR S add_##SUFFIX(long reps) { return add_body<S, L>(reps); }                            \
  ATTR S load_##SUFFIX(const S* a, const S* b, long reps) {                                  \
    return load_body<S, L>(a, b, kArray, reps);                                              \
  }                                                                                          \
  ATTR void store_##SUFFIX(S* p, long reps) { store_body<S, L>(p, kArray / 4, reps); }       \
  ATTR void exp_##SUFFIX(const S* x, S* y, long reps) { exp_body<S, L>(x, y, 256, reps); }   \
  ATTR S load_l2_##SUFFIX(const S* a, const S* b, long reps) {                               \
    return load_body<S, L>(a, b, kL2Array, reps);                                            \
  }

FLOOR_KERNELS(FLOOR_PLAIN, d128, double, 2)
FLOOR_KERNELS(FLOOR_PLAIN, f128, float, 4)
FLOOR_KERNELS(FLOOR_FMA, d256, double, 4)
FLOOR_KERNELS(FLOOR_FMA, f256, float, 8)
FLOOR_KERNELS(FLOOR_AVX512, d512, double, 8)
FLOOR_KERNELS(FLOOR_AVX512, f512, float, 16)
// FMA needs the FMA target at every width; the plain 128-bit kernels above are SSE2.
FLOOR_FMA double fma_d128(long reps) { return fma_body<double, 2>(reps); }
FLOOR_FMA float fma_f128(long reps) { return fma_body<float, 4>(reps); }
FLOOR_FMA double fma_d256(long reps) { return fma_body<double, 4>(reps); }
FLOOR_FMA float fma_f256(long reps) { return fma_body<float, 8>(reps); }
FLOOR_AVX512 double fma_d512(long reps) { return fma_body<double, 8>(reps); }
FLOOR_AVX512 float fma_f512(long reps) { return fma_body<float, 16>(reps); }
FLOOR_FMA double fma_d1(long reps) { return fma_body<double, 1>(reps); }
FLOOR_FMA float fma_f1(long reps) { return fma_body<float, 1>(reps); }
FLOOR_PLAIN double add_d1(long reps) { return add_body<double, 1>(reps); }
FLOOR_PLAIN float add_f1(long reps) { return add_body<float, 1>(reps); }
FLOOR_PLAIN double load_d1(const double* a, const double* b, long reps) {
  return load_body<double, 1>(a, b, kArray, reps);
}
FLOOR_PLAIN float load_f1(const float* a, const float* b, long reps) {
  return load_body<float, 1>(a, b, kArray, reps);
}
FLOOR_PLAIN double load_l2_d1(const double* a, const double* b, long reps) {
  return load_body<double, 1>(a, b, kL2Array, reps);
}
FLOOR_PLAIN float load_l2_f1(const float* a, const float* b, long reps) {
  return load_body<float, 1>(a, b, kL2Array, reps);
}
FLOOR_PLAIN void store_d1(double* p, long reps) { store_body<double, 1>(p, kArray / 4, reps); }
FLOOR_PLAIN void store_f1(float* p, long reps) { store_body<float, 1>(p, kArray / 4, reps); }
FLOOR_PLAIN void exp_d1(const double* x, double* y, long reps) { exp_body1<double>(x, y, 256, reps); }
FLOOR_PLAIN void exp_f1(const float* x, float* y, long reps) { exp_body1<float>(x, y, 256, reps); }

template <typename S>
struct Kernels {
  S (*fma)(long);
  S (*add)(long);
  S (*load)(const S*, const S*, long);
  void (*store)(S*, long);
  void (*exp)(const S*, S*, long);
  S (*load_l2)(const S*, const S*, long);
};

template <typename S>
Kernels<S> kernels(int bytes);
template <>
Kernels<double> kernels<double>(int bytes) {
  switch (bytes) {
    case 0: return {fma_d1, add_d1, load_d1, store_d1, exp_d1, load_l2_d1};
    case 16: return {fma_d128, add_d128, load_d128, store_d128, exp_d128, load_l2_d128};
    case 32: return {fma_d256, add_d256, load_d256, store_d256, exp_d256, load_l2_d256};
    default: return {fma_d512, add_d512, load_d512, store_d512, exp_d512, load_l2_d512};
  }
}
template <>
Kernels<float> kernels<float>(int bytes) {
  switch (bytes) {
    case 0: return {fma_f1, add_f1, load_f1, store_f1, exp_f1, load_l2_f1};
    case 16: return {fma_f128, add_f128, load_f128, store_f128, exp_f128, load_l2_f128};
    case 32: return {fma_f256, add_f256, load_f256, store_f256, exp_f256, load_l2_f256};
    default: return {fma_f512, add_f512, load_f512, store_f512, exp_f512, load_l2_f512};
  }
}

/// Instructions (or, for exp, numbers) per second of one stream kind at one
/// width, as the counter "G_per_s" (10^9 per second).
template <typename S>
void BM_Peak(benchmark::State& state) {
  const auto kind = static_cast<Kind>(state.range(0));
  const int bytes = static_cast<int>(state.range(1));
  const int lanes = bytes == 0 ? 1 : bytes / static_cast<int>(sizeof(S));
  if (!width_supported(bytes) || (kind == Kind::fma && !fma_supported())) {
    state.SkipWithError("the CPU lacks this width");
    return;
  }
  static Arrays<S> arrays;
  static const struct L2Arrays {
    std::vector<S> a = std::vector<S>(kL2Array, S(0.75)), b = std::vector<S>(kL2Array, S(0.5));
  } l2;
  const Kernels<S> k = kernels<S>(bytes);
  double per_call = 0;  // instructions (numbers for exp) per call
  for (auto _ : state) {
    switch (kind) {
      case Kind::fma:
        benchmark::DoNotOptimize(k.fma(kReps));
        per_call = double(kStreams) * kReps;
        break;
      case Kind::add:
        benchmark::DoNotOptimize(k.add(kReps));
        per_call = double(kStreams) * kReps;
        break;
      case Kind::load:
        benchmark::DoNotOptimize(k.load(arrays.a, arrays.y, 16));
        per_call = 2.0 * (kArray / (kStreams * lanes)) * kStreams * 16;
        break;
      case Kind::store:
        k.store(arrays.y, 64);
        per_call = double(kArray / 4 / lanes) * 64;
        break;
      case Kind::exp:
        k.exp(arrays.b, arrays.y, 64);
        per_call = 256.0 * 64;
        break;
      case Kind::load_l2:
        benchmark::DoNotOptimize(k.load_l2(l2.a.data(), l2.b.data(), 2));
        per_call = 2.0 * (kL2Array / (kStreams * lanes)) * kStreams * 2;
        break;
    }
    benchmark::ClobberMemory();
  }
  state.counters["G_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * per_call * 1e-9, benchmark::Counter::kIsRate);
}

// ------------------------------------------------------------- the steps

template <typename S>
void BM_FloorNNStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  auto ctl = neurov_bench::nn_controller<S>(n);
  V6<S> tau;
  neurov_bench::over_ring<S>(state, [&](const StepInput<S>& x) {
    benchmark::DoNotOptimize(ctl.step(x.eta, x.nu, x.eta_d, x.eta_d_dot, x.eta_d_ddot, tau));
    benchmark::DoNotOptimize(tau.data());
  });
}

template <typename S>
void BM_FloorTrackingError(benchmark::State& state) {
  const V6<S> lambda = V6<S>::Constant(S(0.5));
  neurov::TrackingError<S> e;
  neurov_bench::over_ring<S>(state, [&](const StepInput<S>& x) {
    benchmark::DoNotOptimize(
        neurov::compute_tracking_error(x.eta, x.nu, x.eta_d, x.eta_d_dot, x.eta_d_ddot, lambda, e));
    benchmark::DoNotOptimize(&e);
  });
}

void peak_args(benchmark::internal::Benchmark* b) {
  for (int kind = 0; kind <= 5; ++kind)
    for (int bytes : {0, 16, 32, 64}) b->Args({kind, bytes});
}

// --------------------------------------------------------------- the bound

/// Keeps each benchmark's CPU time (ns) and G_per_s counter: the median
/// when repetitions are aggregated, else the last run.
class Collector : public benchmark::ConsoleReporter {
 public:
  struct Figure {
    double ns = 0, rate = 0;
  };
  std::map<std::string, Figure> figures;

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name != "median") continue;
      Figure f;
      f.ns = r.GetAdjustedCPUTime() * 1e9 / benchmark::GetTimeUnitMultiplier(r.time_unit);
      const auto it = r.counters.find("G_per_s");
      if (it != r.counters.end()) f.rate = it->second.value * 1e9;
      figures[r.run_name.function_name + "/" + r.run_name.args] = f;
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

/// The width the NN step's kernels run at (core/vector_unit.hpp's dispatch).
int kernel_bytes() {
  const auto isa = neurov::detail::kernel_isa();
  if (isa == neurov::detail::KernelIsa::avx512) return 64;
  if (isa == neurov::detail::KernelIsa::avx2) return 32;
  return neurov::detail::kBuildVectorBytes;
}

template <typename S>
void print_bounds(const Collector& c, const char* type, int bytes) {
  const auto rate = [&](Kind kind) {
    const std::string key = std::string("BM_Peak<") + type + ">/" +
                            std::to_string(static_cast<int>(kind)) + "/" + std::to_string(bytes);
    const auto it = c.figures.find(key);
    return it == c.figures.end() ? 0.0 : it->second.rate;
  };
  const double lanes = bytes == 0 ? 1 : bytes / static_cast<double>(sizeof(S));
  const CentreCounts n = centre_counts<S>();
  struct Term {
    const char* name;
    double ns;
  };
  // ns per centre for each resource; exp's rate is already per number.
  const Term terms[] = {
      {"fma", n.fma / lanes / rate(Kind::fma) * 1e9},
      {"add", n.add / lanes / rate(Kind::add) * 1e9},
      {"load", n.loads / lanes / rate(Kind::load) * 1e9},
      {"store", n.stores / lanes / rate(Kind::store) * 1e9},
      {"exp", n.exps / rate(Kind::exp) * 1e9},
  };
  const Term* worst = &terms[0];
  std::printf("\n%s, kernels at %d bits: ns per centre by resource:", type, bytes * 8);
  for (const Term& t : terms) {
    std::printf(" %s %.3f", t.name, t.ns);
    if (t.ns > worst->ns) worst = &t;
  }
  const auto fig = [&](const std::string& key) {
    const auto it = c.figures.find(key);
    return it == c.figures.end() ? 0.0 : it->second.ns;
  };
  const double track = fig(std::string("BM_FloorTrackingError<") + type + ">/");
  // What does not fit in L1 must come from L2 at every step: the numbers a
  // step reads per centre (centres, 1/(2 sigma^2), rate, W) beyond the L1's
  // size, at the L2 stream rate of the same run.
  double l1_bytes = 0;
  for (const auto& cache : benchmark::CPUInfo::Get().caches)
    if (cache.level == 1 && cache.type == "Data") l1_bytes = cache.size;
  const double l2_bytes_per_ns = rate(Kind::load_l2) * lanes * sizeof(S) * 1e-9;
  std::printf("\n  per centre %.3f ns (%s); tracking error %.1f ns; L1d %.0f KiB, L2 stream %.1f "
              "B/ns\n",
              worst->ns, worst->name, track, l1_bytes / 1024, l2_bytes_per_ns);
  std::printf("  %6s %10s %10s %10s %10s %8s\n", "N", "arith ns", "L2 ns", "bound ns", "step ns",
              "ratio");
  for (int centres : {64, 256, 1024}) {
    const double arith = centres * worst->ns;
    const double from_l2 = std::max(0.0, centres * n.loads * sizeof(S) - l1_bytes);
    const double l2 = l2_bytes_per_ns > 0 ? from_l2 / l2_bytes_per_ns : 0.0;
    const double bound = track + std::max(arith, l2);
    const double step = fig(std::string("BM_FloorNNStep<") + type + ">/" + std::to_string(centres));
    std::printf("  %6d %10.1f %10.1f %10.1f %10.1f %8.2f\n", centres, arith, l2, bound, step,
                step / bound);
  }
}

}  // namespace

BENCHMARK_TEMPLATE(BM_Peak, double)->Apply(peak_args);
BENCHMARK_TEMPLATE(BM_Peak, float)->Apply(peak_args);
BENCHMARK_TEMPLATE(BM_FloorTrackingError, double);
BENCHMARK_TEMPLATE(BM_FloorTrackingError, float);
BENCHMARK_TEMPLATE(BM_FloorNNStep, double)->Arg(64)->Arg(256)->Arg(1024);
BENCHMARK_TEMPLATE(BM_FloorNNStep, float)->Arg(64)->Arg(256)->Arg(1024);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  Collector collector;
  benchmark::RunSpecifiedBenchmarks(&collector);
  std::printf("\nLower bound of the NN step (bench/README.md, \"The floor\"): the tracking\n"
              "error as measured plus N x the slowest resource per centre, all from this run.\n");
  print_bounds<double>(collector, "double", kernel_bytes());
  print_bounds<float>(collector, "float", kernel_bytes());
  benchmark::Shutdown();
  return 0;
}
