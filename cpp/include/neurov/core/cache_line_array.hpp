// A heap array of scalars that starts on a 64-byte cache line.
//
// Eigen aligns a dynamic matrix to 16 bytes (EIGEN_MAX_ALIGN_BYTES of the
// build), so an AVX2 or AVX-512 load of it crosses a cache line or not
// depending on where the block landed, and a kernel's time moved with the
// heap (bench/heap_offset.py). Raising Eigen's alignment would change the ABI
// of every unit that shares Eigen objects with neurov; this array instead
// allocates one cache line more and starts at the first boundary inside. A
// copy lands elsewhere, so it moves its numbers to its own boundary (a move
// keeps the block, and the boundary with it).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <utility>

namespace neurov {
namespace detail {

template <typename S>
class CacheLineArray {
 public:
  static constexpr std::size_t kLine = 64;

  CacheLineArray() = default;
  CacheLineArray(const CacheLineArray& other) : block_(other.block_), size_(other.size_) {
    realign(other.lead());
  }
  CacheLineArray(CacheLineArray&& other) noexcept { *this = std::move(other); }
  CacheLineArray& operator=(const CacheLineArray& other) {
    if (this != &other) {
      block_ = other.block_;
      size_ = other.size_;
      realign(other.lead());
    }
    return *this;
  }
  CacheLineArray& operator=(CacheLineArray&& other) noexcept {
    if (this != &other) {
      const Eigen::Index from = other.lead();
      block_ = std::move(other.block_);  // Eigen swaps the blocks: nothing moves
      size_ = other.size_;
      other.size_ = 0;
      realign(from);
    }
    return *this;
  }

  /// n numbers, uninitialised; allocates (only here and in a copy).
  void resize(Eigen::Index n) {
    block_.resize(n + static_cast<Eigen::Index>(kLine / sizeof(S)));
    size_ = n;
  }
  Eigen::Index size() const noexcept { return size_; }
  S* data() noexcept { return block_.data() + lead(); }
  const S* data() const noexcept { return block_.data() + lead(); }

 private:
  /// Numbers before the first cache-line boundary of the block (Eigen's
  /// blocks are aligned to at least sizeof(S), so this is whole numbers).
  Eigen::Index lead() const noexcept {
    const auto address = reinterpret_cast<std::uintptr_t>(block_.data());
    return static_cast<Eigen::Index>(((kLine - address % kLine) % kLine) / sizeof(S));
  }
  /// After block_ was taken from an array whose numbers began `from` numbers
  /// into its block: moves them to this block's boundary if that differs.
  void realign(Eigen::Index from) noexcept {
    if (size_ > 0 && lead() != from)
      std::memmove(data(), block_.data() + from, static_cast<std::size_t>(size_) * sizeof(S));
  }

  Eigen::Matrix<S, Eigen::Dynamic, 1> block_;
  Eigen::Index size_ = 0;
};

}  // namespace detail
}  // namespace neurov
