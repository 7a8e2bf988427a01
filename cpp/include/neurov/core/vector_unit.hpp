// The vector unit the hot loops run on (the RBF network's, control/
// rbf_kernels.hpp, and the waves', sim/waves.hpp): vectors of L lanes, and
// which copy of the loops a CPU runs.
//
// With GCC or Clang the loops are written on vector-extension types of L
// lanes; elsewhere they run with L = 1 (plain scalars).
//
// Runtime dispatch (x86-64, GCC or Clang): a build for the x86-64 baseline
// (SSE2, what pip and most distributions compile) also carries AVX2+FMA and
// AVX-512 copies of the loops and picks one from the CPU at the first call.
// They round differently from the SSE2 copy (FMA, and sums split over a
// different number of lanes), so the same binary can differ in the last bits
// between CPUs. The environment variable NEUROV_KERNEL, read at the first
// call, pins the copy: "generic" (the build's own loops), "avx2" or "avx512"
// (each only where the CPU has it, else the best below it); unset, empty or
// "auto" picks the best the CPU has. Define NEUROV_NO_RUNTIME_DISPATCH for
// the build's loops everywhere; builds for a newer baseline (-march=native,
// -mavx2) compile the loops for it and need no dispatch.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <type_traits>

#include "neurov/core/config.hpp"

#if !defined(NEUROV_NO_RUNTIME_DISPATCH) && (defined(__GNUC__) || defined(__clang__)) && \
    defined(__x86_64__) && !defined(__AVX2__)
#define NEUROV_RUNTIME_DISPATCH 1
#else
#define NEUROV_RUNTIME_DISPATCH 0
#endif

#if defined(__GNUC__) || defined(__clang__)
#define NEUROV_VECTOR_EXTENSIONS 1
#define NEUROV_RESTRICT __restrict__
#else
#define NEUROV_VECTOR_EXTENSIONS 0
#define NEUROV_RESTRICT
#endif

namespace neurov {
namespace detail {

// ---------------------------------------------------------------- lane types

template <typename S, int L>
struct VecType {
#if NEUROV_VECTOR_EXTENSIONS
  typedef S type __attribute__((vector_size(L * sizeof(S))));
#else
  static_assert(L == 1, "vector lanes need GCC or Clang vector extensions");
  typedef S type;
#endif
};
template <typename S>
struct VecType<S, 1> {
  typedef S type;
};
template <typename S, int L>
using Vec = typename VecType<S, L>::type;

/// Unsigned integers of the scalar's width, for bit manipulation.
template <typename S>
using UintOf = std::conditional_t<sizeof(S) == 8, std::uint64_t, std::uint32_t>;

template <typename S, int L>
NEUROV_ALWAYS_INLINE void load(Vec<S, L>& v, const S* p) noexcept {
  std::memcpy(&v, p, sizeof v);
}

template <typename S, int L>
NEUROV_ALWAYS_INLINE void store(S* p, const Vec<S, L>& v) noexcept {
  std::memcpy(p, &v, sizeof v);
}

// Vectors go in and out of the helpers by reference only: a 32- or 64-byte
// vector passed by value changes the calling convention with AVX, and GCC
// warns about that (-Wpsabi) in every build for the baseline. A scalar
// broadcast is written V{} + x, for one lane as for many.

/// Lanes of a vector unit of `bytes` for scalars S (1: plain scalars).
template <typename S, int bytes>
constexpr int lanes_for() noexcept {
  return NEUROV_VECTOR_EXTENSIONS && bytes / static_cast<int>(sizeof(S)) >= 2
             ? bytes / static_cast<int>(sizeof(S))
             : 1;
}

/// Register width of the vector unit the build itself targets.
#if defined(__AVX512F__)
constexpr int kBuildVectorBytes = 64;
#elif defined(__AVX__)
constexpr int kBuildVectorBytes = 32;
#elif defined(__SSE2__) || defined(__ARM_NEON) || defined(__ALTIVEC__)
constexpr int kBuildVectorBytes = 16;
#else
constexpr int kBuildVectorBytes = 0;  // no vector unit: plain scalars
#endif

// ------------------------------------------------------------------ dispatch

enum class KernelIsa : std::uint8_t { build = 0, avx2 = 1, avx512 = 2 };

#if NEUROV_RUNTIME_DISPATCH
#define NEUROV_TARGET_AVX2 __attribute__((target("avx2,fma"), noinline))
#define NEUROV_TARGET_AVX512 \
  __attribute__((target("avx512f,avx512vl,avx512dq,avx512bw,avx2,fma"), noinline))

/// The widest copy of the loops this CPU can run.
inline KernelIsa detect_kernel_isa() noexcept {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw"))
    return KernelIsa::avx512;
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return KernelIsa::avx2;
  return KernelIsa::build;
}

/// The copy a NEUROV_KERNEL value asks for, capped at what the CPU supports
/// (a request the CPU cannot run would be an illegal instruction); an unset,
/// empty, "auto" or unknown value gives `supported`.
inline KernelIsa requested_kernel_isa(const char* request, KernelIsa supported) noexcept {
  const auto is = [request](const char* name) {
    return request != nullptr && std::strcmp(request, name) == 0;
  };
  const KernelIsa want = is("generic") ? KernelIsa::build
                         : is("avx2")  ? KernelIsa::avx2
                                       : supported;
  return want < supported ? want : supported;
}

// The choice lives in a constant-initialised atomic, not a function-local
// static: that would need a thread-safe guard (__cxa_guard_acquire from the
// C++ runtime), which C firmware linking neurov_c does not have. Threads that
// race at the first call all compute and store the same value.
constexpr std::uint8_t kKernelIsaUnset = 0xff;
inline std::atomic<std::uint8_t> kernel_isa_choice{kKernelIsaUnset};

/// The copy in use was asked for (NEUROV_KERNEL naming one, or
/// set_kernel_isa), not picked from the CPU: a kernel whose wider copy is
/// not the faster one everywhere runs it only when asked (plant_block.hpp).
inline std::atomic<bool> kernel_isa_pinned{false};

inline KernelIsa kernel_isa() noexcept {
  std::uint8_t isa = kernel_isa_choice.load(std::memory_order_relaxed);
  if (isa == kKernelIsaUnset) {
    const char* request = std::getenv("NEUROV_KERNEL");
    isa = static_cast<std::uint8_t>(requested_kernel_isa(request, detect_kernel_isa()));
    const bool named = request != nullptr && (std::strcmp(request, "generic") == 0 ||
                                              std::strcmp(request, "avx2") == 0 ||
                                              std::strcmp(request, "avx512") == 0);
    kernel_isa_pinned.store(named, std::memory_order_relaxed);
    kernel_isa_choice.store(isa, std::memory_order_relaxed);
  }
  return static_cast<KernelIsa>(isa);
}

/// Switches the copy for the process (capped as NEUROV_KERNEL is); returns
/// the one in use. For tests and benchmarks, not while a network steps.
inline KernelIsa set_kernel_isa(KernelIsa want) noexcept {
  const KernelIsa isa = want < detect_kernel_isa() ? want : detect_kernel_isa();
  kernel_isa_pinned.store(true, std::memory_order_relaxed);
  kernel_isa_choice.store(static_cast<std::uint8_t>(isa), std::memory_order_relaxed);
  return isa;
}
#else
inline KernelIsa kernel_isa() noexcept { return KernelIsa::build; }
inline KernelIsa set_kernel_isa(KernelIsa) noexcept { return KernelIsa::build; }
#endif

/// Which copy of the loops runs here: "avx512" or "avx2" (dispatched), or
/// the build's own: "avx512-build", "avx2-build", "avx", "sse2", "neon",
/// "scalar".
inline const char* kernel_isa_name() noexcept {
  const KernelIsa isa = kernel_isa();
  if (isa != KernelIsa::build) return isa == KernelIsa::avx512 ? "avx512" : "avx2";
#if defined(__AVX512F__)
  return "avx512-build";
#elif defined(__AVX2__)
  return "avx2-build";
#elif defined(__AVX__)
  return "avx";
#elif defined(__SSE2__)
  return "sse2";
#elif defined(__ARM_NEON)
  return "neon";
#else
  return "scalar";
#endif
}

}  // namespace detail
}  // namespace neurov
