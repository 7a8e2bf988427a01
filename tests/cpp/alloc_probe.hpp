// The allocation probe shared by the alloc_*.cpp tests (one executable), with
// the typed suites of scalar_suite.hpp.
// Include it first, before any Eigen header. Two independent detectors watch
// a window around the hot calls:
//  * a counting replacement of the global operator new (every C++
//    allocation); the replacement itself is defined once, in
//    alloc_foundation.cpp, on the counting functions below;
//  * Eigen's EIGEN_RUNTIME_NO_MALLOC check. Eigen allocates with std::malloc,
//    which operator new never sees, and reports through eigen_assert, which
//    NDEBUG (Release) compiles away. So eigen_assert is redefined here, before
//    any Eigen header, to count instead of being dropped; everything is
//    inline, so each translation unit's copy of Eigen's inline functions
//    reports to the same counter.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <new>

namespace alloc_probe {
inline std::atomic<long> eigen_assert_failures{0};
inline void eigen_assert_failed(const char* expr, const char* file, int line) noexcept {
  eigen_assert_failures.fetch_add(1, std::memory_order_relaxed);
  std::fprintf(stderr, "eigen_assert failed: %s (%s:%d)\n", expr, file, line);
}
}  // namespace alloc_probe

#define eigen_assert(x) \
  ((x) ? static_cast<void>(0) : ::alloc_probe::eigen_assert_failed(#x, __FILE__, __LINE__))

#include <Eigen/Core>

#include "scalar_suite.hpp"

#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "alloc_*.cpp must be built with EIGEN_RUNTIME_NO_MALLOC (see tests/cpp/CMakeLists.txt)"
#endif

namespace alloc_probe {

/// Incremented by the global operator new of alloc_foundation.cpp.
inline std::atomic<long> new_calls{0};

inline void* counted_malloc(std::size_t size) {
  new_calls.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}

inline void* counted_aligned(std::size_t size, std::align_val_t align) {
  new_calls.fetch_add(1, std::memory_order_relaxed);
  const std::size_t a = static_cast<std::size_t>(align);
  // aligned_alloc wants a size that is a multiple of the alignment.
  const std::size_t rounded = ((size == 0 ? 1 : size) + a - 1) / a * a;
  return std::aligned_alloc(a, rounded);
}

// Out of line so that GCC, after inlining a delete into a caller of new, does
// not see new paired with free and warn (-Wmismatched-new-delete).
[[gnu::noinline]] inline void release(void* p) noexcept { std::free(p); }

/// Keeps the optimiser from proving an allocation unobservable and removing it.
inline void escape(const void* p) { asm volatile("" : : "g"(p) : "memory"); }

/// Counts of both detectors over one window with Eigen's malloc forbidden.
struct Window {
  long new_calls = 0;
  long eigen_failures = 0;
};

template <typename F>
Window watch(F&& f) {
  const long new_before = new_calls.load();
  const long eigen_before = eigen_assert_failures.load();
  Eigen::internal::set_is_malloc_allowed(false);
  f();
  Eigen::internal::set_is_malloc_allowed(true);
  return {new_calls.load() - new_before, eigen_assert_failures.load() - eigen_before};
}

}  // namespace alloc_probe
