// Arithmetic written once for a "lane type" V: a plain Scalar (one run) or
// a vector of L runs (GCC/Clang vector extensions, core/vector_unit.hpp),
// so that the plant's kernel (model/plant_kernel.hpp) and the sine and
// cosine (core/trig.hpp) are the same code for a single run and for a batch
// of runs in SIMD lanes. Every operation here acts on each lane alone, in
// the same order for every width: lane i of a vector result is bit for bit
// the scalar result for lane i's inputs (where the compiler does not fuse a
// multiply and an add, see plant_kernel.hpp).
//
// A lane mask is what a comparison gives: bool for a Scalar, a vector of
// 0 / -1 integers for a vector. `m ? a : b` selects lane by lane for both.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "neurov/core/config.hpp"
#include "neurov/core/vector_unit.hpp"

namespace neurov {
namespace detail {

/// The scalar of a lane type, and how many lanes it has.
template <typename V, typename = void>
struct LaneTraits {
  using Scalar = V;
  static constexpr int lanes = 1;
};
#if defined(__GNUC__) || defined(__clang__)
template <typename V>
struct LaneTraits<V, std::void_t<decltype(std::declval<V>()[0])>> {
  using Scalar = std::remove_cv_t<std::remove_reference_t<decltype(std::declval<V>()[0])>>;
  static constexpr int lanes = static_cast<int>(sizeof(V) / sizeof(Scalar));
};
#endif

template <typename V>
using LaneScalar = typename LaneTraits<V>::Scalar;
template <typename V>
inline constexpr int kLanes = LaneTraits<V>::lanes;

/// Lane i of v (a Scalar is its own lane 0).
template <typename V>
NEUROV_ALWAYS_INLINE LaneScalar<V> lane(const V& v, int i) noexcept {
  if constexpr (kLanes<V> == 1) {
    (void)i;
    return v;
  } else {
    return v[i];
  }
}

template <typename V>
NEUROV_ALWAYS_INLINE void set_lane(V& v, int i, LaneScalar<V> x) noexcept {
  if constexpr (kLanes<V> == 1) {
    (void)i;
    v = x;
  } else {
    v[i] = x;
  }
}

/// A mask is set in lane i.
template <typename M>
NEUROV_ALWAYS_INLINE bool mask_lane(const M& m, int i) noexcept {
  if constexpr (std::is_same_v<M, bool>) {
    (void)i;
    return m;
  } else {
    return m[i] != 0;
  }
}

/// Any lane of a mask is set.
template <typename M>
NEUROV_ALWAYS_INLINE bool any(const M& m) noexcept {
  if constexpr (std::is_same_v<M, bool>) {
    return m;
  } else {
    bool a = false;
    for (int i = 0; i < static_cast<int>(sizeof(M) / sizeof(m[0])); ++i) a = a || m[i] != 0;
    return a;
  }
}

/// The mask type of lane type V (what V < V gives).
template <typename V>
using MaskOf = decltype(std::declval<V>() < std::declval<V>());

// Vectors leave the helpers below through references only: a 32- or
// 64-byte vector returned by value changes the calling convention with AVX,
// and GCC warns about it (-Wpsabi) once per translation unit, at its end,
// where no pragma of this header reaches. Selects are written `m ? a : b`
// and broadcasts `V{} + x`, both builtin.

/// The unsigned integer of a lane's width, and a lane type's bits.
template <typename V>
using BitsScalar = std::conditional_t<sizeof(LaneScalar<V>) == 8, std::uint64_t, std::uint32_t>;
template <typename V>
using BitsOf = std::conditional_t<kLanes<V> == 1, BitsScalar<V>, Vec<BitsScalar<V>, kLanes<V>>>;
/// The sign bit of a lane.
template <typename V>
inline constexpr BitsScalar<V> kSignBit = BitsScalar<V>(1) << (8 * sizeof(BitsScalar<V>) - 1);

/// The bits of each lane of v, as unsigned integers.
template <typename V>
NEUROV_ALWAYS_INLINE void bits_of(const V& v, BitsOf<V>& u) noexcept {
  std::memcpy(&u, &v, sizeof u);
}

template <typename V>
NEUROV_ALWAYS_INLINE void from_bits(const BitsOf<V>& u, V& v) noexcept {
  std::memcpy(&v, &u, sizeof v);
}

/// |x| lane by lane (clears the sign bit, as std::fabs does).
template <typename V>
NEUROV_ALWAYS_INLINE void lane_abs(const V& x, V& out) noexcept {
  if constexpr (kLanes<V> == 1) {
    out = std::fabs(x);
  } else {
    BitsOf<V> u;
    bits_of(x, u);
    u &= ~kSignBit<V>;
    from_bits(u, out);
  }
}

/// x with the sign of s, lane by lane (std::copysign).
template <typename V>
NEUROV_ALWAYS_INLINE void lane_copysign(const V& x, const V& s, V& out) noexcept {
  if constexpr (kLanes<V> == 1) {
    out = std::copysign(x, s);
  } else {
    BitsOf<V> ux, us;
    bits_of(x, ux);
    bits_of(s, us);
    ux = (ux & ~kSignBit<V>) | (us & kSignBit<V>);
    from_bits(ux, out);
  }
}

/// Clears the lanes of m where x is not finite (x - x is 0 exactly where it is).
template <typename V>
NEUROV_ALWAYS_INLINE void and_finite(MaskOf<V>& m, const V& x) noexcept {
  m = MaskOf<V>(m & (x - x == V{}));
}

}  // namespace detail
}  // namespace neurov
