// Up to kPlantBlockWidth runs' plant steps at once: the RK4 step of
// plant_kernel.hpp on SIMD lanes, each lane a run with its own vehicle,
// state, force, current and step. The batch (sim/batch.hpp) fills a block
// from its lanes, calls plant_rk4_block and reads the states back.
//
// The copies follow the RBF kernels' runtime dispatch (core/vector_unit.hpp:
// the build's own vector width, AVX2 and AVX-512 on x86-64, NEUROV_KERNEL
// pins one), except that the AVX-512 copy runs only when pinned (see
// plant_rk4_block). Unlike the RBF copies these are compiled without fused
// multiply-adds (GCC's fp-contract=off): the single run does each multiply
// and add apart on the x86-64 baseline, and so must every lane for a batch
// to give each run bit for bit what it gives alone.
#pragma once

#include <cstdint>
#include <cstring>

#include "neurov/core/config.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/vector_unit.hpp"
#include "neurov/model/plant_kernel.hpp"

namespace neurov {

/// Runs a block holds: AVX-512's lanes of float.
inline constexpr int kPlantBlockWidth = 16;

/// A block of runs' plants, structure of arrays: x[i][lane].
template <typename Scalar>
struct PlantBlock {
  alignas(64) Scalar coefficients[detail::plant_coef::count][kPlantBlockWidth];
  alignas(64) Scalar eta[6][kPlantBlockWidth];
  alignas(64) Scalar nu[6][kPlantBlockWidth];
  alignas(64) Scalar tau[6][kPlantBlockWidth];
  alignas(64) Scalar current[3][kPlantBlockWidth];
  alignas(64) Scalar h[kPlantBlockWidth];
  std::uint8_t status[kPlantBlockWidth];  ///< rk4_step's Status of each lane
  int lanes = 0;                          ///< lanes in use, from lane 0
};

namespace detail {

#if defined(__GNUC__) && !defined(__clang__)
#define NEUROV_EXACT_LANES optimize("fp-contract=off"),
#else
#define NEUROV_EXACT_LANES
#endif

template <typename Scalar, int L>
NEUROV_ALWAYS_INLINE void plant_rk4_block_lanes(PlantBlock<Scalar>& b) noexcept {
  using V = Vec<Scalar, L>;
  namespace pc = plant_coef;
  // Lanes past b.lanes repeat lane 0 so that no vector meets stale numbers.
  for (int j = b.lanes; j < ((b.lanes + L - 1) / L) * L; ++j) {
    for (int f = 0; f < pc::count; ++f) b.coefficients[f][j] = b.coefficients[f][0];
    for (int i = 0; i < 6; ++i) {
      b.eta[i][j] = b.eta[i][0];
      b.nu[i][j] = b.nu[i][0];
      b.tau[i][j] = b.tau[i][0];
    }
    for (int i = 0; i < 3; ++i) b.current[i][j] = b.current[i][0];
    b.h[j] = b.h[0];
  }
  for (int off = 0; off < b.lanes; off += L) {
    V c[pc::count], eta[6], nu[6], tau[6], current[3], h;
    for (int f = 0; f < pc::count; ++f) load<Scalar, L>(c[f], &b.coefficients[f][off]);
    for (int i = 0; i < 6; ++i) {
      load<Scalar, L>(eta[i], &b.eta[i][off]);
      load<Scalar, L>(nu[i], &b.nu[i][off]);
      load<Scalar, L>(tau[i], &b.tau[i][off]);
    }
    for (int i = 0; i < 3; ++i) load<Scalar, L>(current[i], &b.current[i][off]);
    load<Scalar, L>(h, &b.h[off]);
    Rk4Masks<V> m;
    plant_rk4(c, eta, nu, tau, current, h, m);
    for (int i = 0; i < 6; ++i) {
      store<Scalar, L>(&b.eta[i][off], eta[i]);
      store<Scalar, L>(&b.nu[i][off], nu[i]);
    }
    for (int j = 0; j < L && off + j < b.lanes; ++j)
      b.status[off + j] = static_cast<std::uint8_t>(status_of(m, j));
  }
}

template <typename Scalar>
__attribute__((NEUROV_EXACT_LANES noinline)) inline void plant_rk4_block_build(
    PlantBlock<Scalar>& b) noexcept {
  plant_rk4_block_lanes<Scalar, lanes_for<Scalar, kBuildVectorBytes>()>(b);
}

#if NEUROV_RUNTIME_DISPATCH
template <typename Scalar>
__attribute__((target("avx2"), NEUROV_EXACT_LANES noinline)) inline void plant_rk4_block_avx2(
    PlantBlock<Scalar>& b) noexcept {
  plant_rk4_block_lanes<Scalar, lanes_for<Scalar, 32>()>(b);
}

template <typename Scalar>
__attribute__((target("avx512f,avx512vl,avx512dq,avx512bw,avx2"), NEUROV_EXACT_LANES noinline))
inline void plant_rk4_block_avx512(PlantBlock<Scalar>& b) noexcept {
  plant_rk4_block_lanes<Scalar, lanes_for<Scalar, 64>()>(b);
}
#endif

}  // namespace detail

/// One RK4 step on each of the block's lanes (see plant_kernel.hpp's
/// plant_rk4): states advanced in place where the step succeeded, status[i]
/// as rk4_step would return for lane i. Never allocates, never throws.
template <typename Scalar>
inline void plant_rk4_block(PlantBlock<Scalar>& b) noexcept {
  if (b.lanes <= 0) return;
#if NEUROV_RUNTIME_DISPATCH
  switch (detail::kernel_isa()) {
    case detail::KernelIsa::avx512:
      // Only when asked for: measured, the AVX-512 copy is the slower on the
      // project's machine (a lane-step 88 ns against 68 ns in AVX2, although
      // its 512-bit FMAs issue nearly as fast; bench/README.md).
      if (detail::kernel_isa_pinned.load(std::memory_order_relaxed)) {
        detail::plant_rk4_block_avx512(b);
        return;
      }
      detail::plant_rk4_block_avx2(b);
      return;
    case detail::KernelIsa::avx2:
      detail::plant_rk4_block_avx2(b);
      return;
    default:
      break;
  }
#endif
  detail::plant_rk4_block_build(b);
}

}  // namespace neurov
