// The entry points of the RBF network's loops (rbf_kernel_loops.hpp):
// rbf_basis, nn_output_update and nn_output. Each runs the build's own copy
// of its loop or, where the build dispatches at run time
// (core/vector_unit.hpp: x86-64 built for its baseline), the AVX2+FMA or
// AVX-512 copy compiled here, as the CPU and NEUROV_KERNEL decide at the
// first call.
#pragma once

#include <type_traits>

#include "neurov/control/rbf_kernel_loops.hpp"
#include "neurov/core/vector_unit.hpp"

namespace neurov {
namespace detail {

#if NEUROV_RUNTIME_DISPATCH
template <typename S>
NEUROV_TARGET_AVX2 void basis_avx2(const CentrePanels<S>& c, Index n, Index n_in, const S* x,
                                   const S* inv, S* g) noexcept {
  basis_impl<S, 32>(c, n, n_in, x, inv, g);
}
template <typename S>
NEUROV_TARGET_AVX512 void basis_avx512(const CentrePanels<S>& c, Index n, Index n_in,
                                       const S* x, const S* inv, S* g) noexcept {
  basis_impl<S, 64>(c, n, n_in, x, inv, g);
}
template <typename S>
NEUROV_TARGET_AVX2 S output_update_avx2(S* w, Index n, const S* g, const S* r, const S* a, S dl,
                                        S* y) noexcept {
  return output_update_impl<S, 32>(w, n, g, r, a, dl, y);
}
template <typename S>
NEUROV_TARGET_AVX512 S output_update_avx512(S* w, Index n, const S* g, const S* r, const S* a,
                                            S dl, S* y) noexcept {
  return output_update_impl<S, 64>(w, n, g, r, a, dl, y);
}
template <typename S>
NEUROV_TARGET_AVX2 void output_avx2(const S* w, Index n, const S* g, S* y) noexcept {
  output_impl<S, 32>(w, n, g, y);
}
template <typename S>
NEUROV_TARGET_AVX512 void output_avx512(const S* w, Index n, const S* g, S* y) noexcept {
  output_impl<S, 64>(w, n, g, y);
}
#endif

/// The scalars the dispatched copies are compiled for (others run the build's loops).
template <typename S>
constexpr bool dispatchable() noexcept {
  return std::is_same<S, float>::value || std::is_same<S, double>::value;
}

/// g = exp(-||x_hat - xi_j||^2 inv_j) for n centres in panels.
template <typename S>
inline void rbf_basis(const CentrePanels<S>& packed, Index n, Index n_in, const S* x_hat,
                      const S* inv, S* g) noexcept {
#if NEUROV_RUNTIME_DISPATCH
  if constexpr (dispatchable<S>()) {
    switch (kernel_isa()) {
      case KernelIsa::avx512:
        return basis_avx512<S>(packed, n, n_in, x_hat, inv, g);
      case KernelIsa::avx2:
        return basis_avx2<S>(packed, n, n_in, x_hat, inv, g);
      case KernelIsa::build:
        break;
    }
  }
#endif
  basis_impl<S, kBuildVectorBytes>(packed, n, n_in, x_hat, inv, g);
}

/// The fused pass of the NN step (output_update_body); returns ||W_new||^2.
template <typename S>
inline S nn_output_update(S* w, Index n, const S* g, const S* rates, const S* a, S dl,
                          S* y) noexcept {
#if NEUROV_RUNTIME_DISPATCH
  if constexpr (dispatchable<S>()) {
    switch (kernel_isa()) {
      case KernelIsa::avx512:
        return output_update_avx512<S>(w, n, g, rates, a, dl, y);
      case KernelIsa::avx2:
        return output_update_avx2<S>(w, n, g, rates, a, dl, y);
      case KernelIsa::build:
        break;
    }
  }
#endif
  return output_update_impl<S, kBuildVectorBytes>(w, n, g, rates, a, dl, y);
}

/// y = W g for a 6 x n column-major W.
template <typename S>
inline void nn_output(const S* w, Index n, const S* g, S* y) noexcept {
#if NEUROV_RUNTIME_DISPATCH
  if constexpr (dispatchable<S>()) {
    switch (kernel_isa()) {
      case KernelIsa::avx512:
        return output_avx512<S>(w, n, g, y);
      case KernelIsa::avx2:
        return output_avx2<S>(w, n, g, y);
      case KernelIsa::build:
        break;
    }
  }
#endif
  output_impl<S, kBuildVectorBytes>(w, n, g, y);
}

}  // namespace detail
}  // namespace neurov
