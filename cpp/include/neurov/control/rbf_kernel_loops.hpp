// The inner loops of the RBF network and of the NN controller's step, on
// vectors of L lanes (core/vector_unit.hpp); rbf_kernels.hpp compiles them
// for each vector unit and picks the copy the CPU runs.
//
//   * basis: squared distances from x_hat to a block of centres, accumulated
//     in registers over the inputs, then exp of the block. The centres are
//     read in panels: centre j, input i at (j / pw) pw n_in + i pw + j % pw.
//     A packed copy with pw = one cache line of centres (panel_width) lets a
//     block stream through contiguous memory; the N x n_in column-major
//     matrix itself is the case pw = N, where the inputs of a block sit N
//     apart and for N a multiple of 512 (double) all fall in one L1 set.
//   * output + update: one pass over W (6 x N, column-major) that forms
//     y = W g with the old weights, writes W - a (gamma .* g)^T (with the
//     leakage of the sigma/e-modification) and sums ||W_new||^2.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

#include "neurov/core/config.hpp"
#include "neurov/core/vector_unit.hpp"

namespace neurov {
namespace detail {

using Index = Eigen::Index;

/// Centres per panel of the packed copy: one 64-byte cache line.
template <typename S>
constexpr Index panel_width() noexcept {
  return sizeof(S) >= 64 ? 1 : static_cast<Index>(64 / sizeof(S));
}

/// Size of the packed copy of n centres of n_in inputs.
template <typename S>
constexpr Index packed_centres_size(Index n, Index n_in) noexcept {
  return (n + panel_width<S>() - 1) / panel_width<S>() * panel_width<S>() * n_in;
}

/// Packs the column-major centres (leading dimension ld) into panels:
/// centre j, input i at (j / PW) * PW * n_in + i * PW + j % PW, zero-padded.
template <typename S>
inline void pack_centres(const S* centres, Index ld, Index n, Index n_in, S* out) noexcept {
  constexpr Index pw = panel_width<S>();
  const Index panels = (n + pw - 1) / pw;
  for (Index p = 0; p < panels; ++p)
    for (Index i = 0; i < n_in; ++i)
      for (Index l = 0; l < pw; ++l) {
        const Index j = p * pw + l;
        out[(p * n_in + i) * pw + l] = j < n ? centres[i * ld + j] : S(0);
      }
}

// ------------------------------------------------------------------- exp(x<=0)

/// x <- exp(x) for x <= 0 (larger x are treated as 0), to within 0.7 ulp,
/// and 0 below the smallest normal result rather than a subnormal (a
/// subnormal g changes nothing in tau but can slow every product with it).
/// Branch-free: Cody-Waite reduction x = n ln2 + r with |r| <= ln2 / 2, a
/// Taylor polynomial (to r^13 in double, r^7 in float: truncation below a
/// tenth of an ulp), and 2^n built in the exponent bits.
template <typename S, int L>
NEUROV_ALWAYS_INLINE void exp_nonpositive(Vec<S, L>& x) noexcept {
  using V = Vec<S, L>;
  using U = Vec<UintOf<S>, L>;
  constexpr bool dbl = sizeof(S) == 8;
  // log of the smallest normal number.
  const V lowest = V{} + (dbl ? S(-708.3964185322641) : S(-87.33654475f));
  const V zero = V{};
  const auto underflow = x < lowest;
  x = x < zero ? x : zero;
  x = x > lowest ? x : lowest;
  // Adding 1.5 * 2^(digits - 1) rounds to an integer held in the low bits.
  const V shifter = V{} + (dbl ? S(0x1.8p52) : S(0x1.8p23f));
  const V t = x * S(1.4426950408889634) + shifter;
  const V n = t - shifter;
  // ln2 in two parts; n * hi is exact for every n reached here.
  const V r = (x - n * (dbl ? S(6.93147180369123816490e-01) : S(0.693145751953125f))) -
              n * (dbl ? S(1.90821492927058770002e-10) : S(1.428606765330187045e-06f));
  // 1 + r + r^2 q(r), q evaluated by Estrin's scheme: a Horner chain of
  // thirteen dependent multiply-adds per vector was the slowest part.
  const V r2 = r * r, r4 = r2 * r2;
  V q;
  if constexpr (dbl) {
    const V a0 = S(1.0 / 2.0) + r * S(1.0 / 6.0), a1 = S(1.0 / 24.0) + r * S(1.0 / 120.0),
            a2 = S(1.0 / 720.0) + r * S(1.0 / 5040.0),
            a3 = S(1.0 / 40320.0) + r * S(1.0 / 362880.0),
            a4 = S(1.0 / 3628800.0) + r * S(1.0 / 39916800.0),
            a5 = S(1.0 / 479001600.0) + r * S(1.0 / 6227020800.0);
    const V b0 = a0 + r2 * a1, b1 = a2 + r2 * a3, b2 = a4 + r2 * a5;
    q = b0 + r4 * (b1 + r4 * b2);
  } else {
    const V a0 = S(1.0 / 2.0) + r * S(1.0 / 6.0), a1 = S(1.0 / 24.0) + r * S(1.0 / 120.0),
            a2 = S(1.0 / 720.0) + r * S(1.0 / 5040.0);
    q = a0 + r2 * (a1 + r2 * a2);
  }
  const V p = S(1) + (r + r2 * q);
  // The low bits of t are n: (n + bias) << mantissa bits is 2^n.
  U bits;
  std::memcpy(&bits, &t, sizeof bits);
  bits = (bits + static_cast<UintOf<S>>(dbl ? 1023 : 127)) << (dbl ? 52 : 23);
  V scale;
  std::memcpy(&scale, &bits, sizeof scale);
  const V result = p * scale;
  x = underflow ? zero : result;
}

// ----------------------------------------------------------------- the loops

/// Where the centres are: panels of pw centres (see the top of the file);
/// `padded` when the last panel is zero-filled to pw, so that a vector may
/// read past centre n - 1.
template <typename S>
struct CentrePanels {
  const S* data;
  Index pw;
  bool padded;
};

/// Centres [j0, j0 + NV L) of the panels, j0 a multiple of L and pw of L:
/// g_j = exp(-||x_hat - xi_j||^2 inv_j), with inv and g pointing at the
/// block's first centre. Each centre's sum runs over the
/// inputs in order, as the scalar definition does; the NV L sums are
/// independent, which is what fills the lanes and hides the add latency.
/// PW > 0 is the panel width known at compile time (the packed copy): the
/// panel of a centre is then a shift, not one integer division per vector
/// of every block (which the profile of the double step showed).
template <typename S, int L, int NV, Index PW = 0>
NEUROV_ALWAYS_INLINE void basis_block(const CentrePanels<S>& c, Index n_in, Index j0,
                                      const S* NEUROV_RESTRICT x_hat,
                                      const S* NEUROV_RESTRICT inv, S* NEUROV_RESTRICT g) noexcept {
  using V = Vec<S, L>;
  const Index pw = PW > 0 ? PW : c.pw;
  const S* base[NV];
  V acc[NV];
  for (int v = 0; v < NV; ++v) {
    const Index j = j0 + v * L;
    base[v] = c.data + (j / pw) * pw * n_in + j % pw;
    acc[v] = V{};
  }
  for (Index i = 0; i < n_in; ++i) {
    const V xi = V{} + x_hat[i];
    for (int v = 0; v < NV; ++v) {
      V d;
      load<S, L>(d, base[v] + i * pw);
      d -= xi;
      acc[v] += d * d;
    }
  }
  for (int v = 0; v < NV; ++v) {
    V e;
    load<S, L>(e, inv + v * L);
    e = -acc[v] * e;
    exp_nonpositive<S, L>(e);
    store<S, L>(g + v * L, e);
  }
}

/// Blocks of NV vectors, then NV/2, ..., 1, then the last < L centres: as
/// one vector over the zero padding of the last panel, of which only the
/// real centres are stored, or one at a time without padding (the same sums
/// in the same order in every case; the same numbers in the build's loops,
/// while on the FMA paths the scalar tail can differ from the padded vector
/// in the last bit: tests/cpp/test_kernel_paths.cpp).
template <typename S, int L, int NV, Index PW = 0>
NEUROV_ALWAYS_INLINE void basis_blocks(const CentrePanels<S>& c, Index n, Index n_in, Index j0,
                                       const S* x_hat, const S* inv, S* g) noexcept {
  for (; j0 + NV * L <= n; j0 += NV * L)
    basis_block<S, L, NV, PW>(c, n_in, j0, x_hat, inv + j0, g + j0);
  if constexpr (NV > 1) {
    basis_blocks<S, L, NV / 2, PW>(c, n, n_in, j0, x_hat, inv, g);
  } else if constexpr (L > 1) {
    if (j0 < n && c.padded) {
      S inv_tail[L], g_tail[L];
      for (Index l = 0; l < L; ++l) inv_tail[l] = j0 + l < n ? inv[j0 + l] : S(0);
      basis_block<S, L, 1, PW>(c, n_in, j0, x_hat, inv_tail, g_tail);
      for (Index l = 0; j0 + l < n; ++l) g[j0 + l] = g_tail[l];
    } else {
      for (; j0 < n; ++j0) basis_block<S, 1, 1>(c, n_in, j0, x_hat, inv + j0, g + j0);
    }
  }
}

/// The lanes of vector m (of three) of a pass over P = L / 2 columns of a
/// 6-row column-major matrix: lane l holds column j + (m L + l) / 6. Built
/// from broadcasts of the (at most three) columns the vector spans.
template <typename S, int L, int m>
NEUROV_ALWAYS_INLINE void column_lanes(Vec<S, L>& out, const S* v, Index j) noexcept {
  using V = Vec<S, L>;
  using U = Vec<UintOf<S>, L>;
  constexpr int first = m * L / 6, last = (m * L + L - 1) / 6;
  U lane;
  for (int l = 0; l < L; ++l) lane[l] = static_cast<UintOf<S>>(l);
  out = V{} + v[j + first];
  for (int c = first + 1; c <= last; ++c)
    out = lane >= static_cast<UintOf<S>>(6 * c - m * L) ? V{} + v[j + c] : out;
}

/// Vector m of a pass as column_lanes() builds it, from a vector `in` of the
/// next L values by one shuffle (where L values remain to be read).
template <typename S, int L, int m, std::size_t... I>
NEUROV_ALWAYS_INLINE void spread_columns(Vec<S, L>& out, const Vec<S, L>& in,
                                         std::index_sequence<I...>) noexcept {
#if defined(__clang__)
  out = __builtin_shufflevector(in, in, ((m * L + static_cast<int>(I)) / 6)...);
#else
  using Mask = Vec<std::conditional_t<sizeof(S) == 8, std::int64_t, std::int32_t>, L>;
  out = __builtin_shuffle(in, Mask{((m * L + static_cast<int>(I)) / 6)...});
#endif
}

/// One pass over P = L / 2 columns (three vectors of W) given the column
/// lanes of g, of rate .* g (cv) and, for the leakage, of the rates.
template <typename S, int L, bool Update, bool Leak>
NEUROV_ALWAYS_INLINE void output_update_pass(S* NEUROV_RESTRICT wc, const Vec<S, L>* gv,
                                             const Vec<S, L>* cv, const Vec<S, L>* rv,
                                             const Vec<S, L>* av, S dl, Vec<S, L>* yv,
                                             Vec<S, L>* nv) noexcept {
  using V = Vec<S, L>;
  for (int m = 0; m < 3; ++m) {
    V wk;
    load<S, L>(wk, wc + m * L);
    yv[m] += wk * gv[m];
    if constexpr (Update) {
      if constexpr (Leak) {
        const V keep = S(1) - dl * rv[m];
        wk *= V{} < keep ? keep : V{};
      }
      wk -= cv[m] * av[m];
      store<S, L>(wc + m * L, wk);
      nv[m] += wk * wk;
    }
  }
}

/// y = W g (W: 6 x n, column-major), and with Update also, in the same pass,
/// W_j <- keep_j W_j - (rate_j g_j) a with keep_j = max(0, 1 - dl rate_j)
/// (Leak) or 1; returns ||W_new||_F^2 (0 without Update). A pass covers
/// P = L / 2 columns, 6P = 3L contiguous numbers: three whole vectors.
template <typename S, int L, bool Update, bool Leak>
NEUROV_ALWAYS_INLINE S output_update_body(S* NEUROV_RESTRICT w, Index n,
                                          const S* NEUROV_RESTRICT g,
                                          const S* NEUROV_RESTRICT rates,
                                          const S* NEUROV_RESTRICT a, S dl,
                                          S* NEUROV_RESTRICT y) noexcept {
  S ys[6] = {S(0), S(0), S(0), S(0), S(0), S(0)};
  S norm2 = S(0);
  Index j = 0;
  if constexpr (L >= 2) {
    using V = Vec<S, L>;
    constexpr int P = L / 2;
    V av[3], yv[3], nv[3];
    S pattern[3 * L];  // a repeated down the pass: lane l of vector m is a[(m L + l) % 6]
    for (int k = 0; k < 3 * L; ++k) pattern[k] = Update ? a[k % 6] : S(0);
    for (int m = 0; m < 3; ++m) {
      load<S, L>(av[m], pattern + m * L);
      yv[m] = nv[m] = V{};
    }
    V gv[3], cv[3], rv[3];
    // Lanes of g and of rate .* g by shuffles of one load each: the product
    // formed once per centre, before it is spread over the six rows (the
    // same numbers as forming it lane by lane), and the rates spread only
    // for the leakage...
    constexpr auto lanes = std::make_index_sequence<L>{};
    const Index passes = n / P, loaded = n >= L ? (n - L) / P + 1 : 0;
    for (Index p = 0; p < loaded; ++p, j += P) {
      V gl, rl;
      load<S, L>(gl, g + j);
      spread_columns<S, L, 0>(gv[0], gl, lanes);
      spread_columns<S, L, 1>(gv[1], gl, lanes);
      spread_columns<S, L, 2>(gv[2], gl, lanes);
      if constexpr (Update) {
        load<S, L>(rl, rates + j);
        const V cl = rl * gl;
        spread_columns<S, L, 0>(cv[0], cl, lanes);
        spread_columns<S, L, 1>(cv[1], cl, lanes);
        spread_columns<S, L, 2>(cv[2], cl, lanes);
        if constexpr (Leak) {
          spread_columns<S, L, 0>(rv[0], rl, lanes);
          spread_columns<S, L, 1>(rv[1], rl, lanes);
          spread_columns<S, L, 2>(rv[2], rl, lanes);
        }
      }
      output_update_pass<S, L, Update, Leak>(w + 6 * j, gv, cv, rv, av, dl, yv, nv);
    }
    // ...and near the end, where a load of L would read past n, broadcasts.
    for (Index p = loaded; p < passes; ++p, j += P) {
      column_lanes<S, L, 0>(gv[0], g, j);
      column_lanes<S, L, 1>(gv[1], g, j);
      column_lanes<S, L, 2>(gv[2], g, j);
      if constexpr (Update) {
        column_lanes<S, L, 0>(rv[0], rates, j);
        column_lanes<S, L, 1>(rv[1], rates, j);
        column_lanes<S, L, 2>(rv[2], rates, j);
        for (int m = 0; m < 3; ++m) cv[m] = rv[m] * gv[m];
      }
      output_update_pass<S, L, Update, Leak>(w + 6 * j, gv, cv, rv, av, dl, yv, nv);
    }
    for (int m = 0; m < 3; ++m)
      for (int l = 0; l < L; ++l) {
        ys[(m * L + l) % 6] += yv[m][l];
        norm2 += nv[m][l];
      }
    // Where the passes stopped, stated rather than carried in j: for a fixed
    // N GCC otherwise loses the bound and warns of out-of-range iterations
    // in the loop below.
    j = passes * P;
  }
  for (; j < n; ++j) {
    for (int i = 0; i < 6; ++i) {
      S wk = w[6 * j + i];
      ys[i] += wk * g[j];
      if constexpr (Update) {
        if constexpr (Leak) {
          const S keep = S(1) - dl * rates[j];
          wk *= S(0) < keep ? keep : S(0);
        }
        wk -= (rates[j] * g[j]) * a[i];
        w[6 * j + i] = wk;
        norm2 += wk * wk;
      }
    }
  }
  for (int i = 0; i < 6; ++i) y[i] = ys[i];
  return norm2;
}

// ------------------------------------------- the loops for one vector unit
// Each for a vector unit of `bytes` (lanes_for; 0: plain scalars): the
// build's own copy, and the dispatched ones of rbf_kernels.hpp.

template <typename S, int bytes>
NEUROV_ALWAYS_INLINE void basis_impl(const CentrePanels<S>& c, Index n, Index n_in,
                                     const S* x_hat, const S* inv, S* g) noexcept {
  constexpr int L = lanes_for<S, bytes>();
  // Eight vectors of sums: the add latency hidden, registers to spare. Panels
  // a vector could straddle (pw no multiple of L) are read one lane at a time.
  constexpr Index packed = panel_width<S>();
  if (c.pw == packed && packed % L == 0)
    basis_blocks<S, L, 8, packed>(c, n, n_in, 0, x_hat, inv, g);
  else if (c.pw % L == 0 || c.pw >= n)
    basis_blocks<S, L, 8>(c, n, n_in, 0, x_hat, inv, g);
  else
    basis_blocks<S, 1, 8>(c, n, n_in, 0, x_hat, inv, g);
}

template <typename S, int bytes>
NEUROV_ALWAYS_INLINE S output_update_impl(S* w, Index n, const S* g, const S* rates, const S* a,
                                          S dl, S* y) noexcept {
  constexpr int L = lanes_for<S, bytes>();
  return dl > S(0) ? output_update_body<S, L, true, true>(w, n, g, rates, a, dl, y)
                   : output_update_body<S, L, true, false>(w, n, g, rates, a, dl, y);
}

template <typename S, int bytes>
NEUROV_ALWAYS_INLINE void output_impl(const S* w, Index n, const S* g, S* y) noexcept {
  // The read-only pass: w is not written when Update is false.
  (void)output_update_body<S, lanes_for<S, bytes>(), false, false>(const_cast<S*>(w), n, g,
                                                                     nullptr, nullptr, S(0), y);
}

}  // namespace detail
}  // namespace neurov
