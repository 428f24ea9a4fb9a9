#pragma once
// One N-bit occlusion mask per receiver, the common output of every backend. Bit i of a row is
// set when ray i of that receiver is blocked.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace exao {

/// AO from a receiver's blocked-ray count: 1 - blocked / N, 1 fully open, 0 fully occluded (glTF
/// occlusion semantics). The one formula every output of exao uses.
[[nodiscard]] inline float ao_from_blocked(int blocked, int samples) {
  return 1.0f - static_cast<float>(blocked) / static_cast<float>(samples);
}

class MaskSet {
 public:
  MaskSet() = default;
  MaskSet(std::size_t receivers, int samples)
      : samples_(samples), words_((samples + 63) / 64), bits_(receivers * static_cast<std::size_t>(words_), 0) {}

  [[nodiscard]] std::size_t size() const { return words_ == 0 ? 0 : bits_.size() / static_cast<std::size_t>(words_); }
  [[nodiscard]] int samples() const { return samples_; }
  [[nodiscard]] int words() const { return words_; }
  [[nodiscard]] std::span<std::uint64_t> row(std::size_t receiver) {
    return {bits_.data() + receiver * static_cast<std::size_t>(words_), static_cast<std::size_t>(words_)};
  }
  [[nodiscard]] std::span<const std::uint64_t> row(std::size_t receiver) const {
    return {bits_.data() + receiver * static_cast<std::size_t>(words_), static_cast<std::size_t>(words_)};
  }
  [[nodiscard]] bool blocked(std::size_t receiver, int ray) const {
    return (row(receiver)[static_cast<std::size_t>(ray / 64)] >> (ray % 64)) & 1u;
  }
  /// Number of blocked rays of a receiver.
  [[nodiscard]] int blocked_count(std::size_t receiver) const {
    int n = 0;
    for (const std::uint64_t w : row(receiver)) n += std::popcount(w);
    return n;
  }
  /// ao_from_blocked of the receiver's row.
  [[nodiscard]] float ao(std::size_t receiver) const { return ao_from_blocked(blocked_count(receiver), samples_); }
  [[nodiscard]] const std::vector<std::uint64_t>& bits() const { return bits_; }
  /// Every row, back to back: size() * words() words.
  [[nodiscard]] std::span<std::uint64_t> all_rows() { return bits_; }

 private:
  int samples_ = 0;
  int words_ = 0;
  std::vector<std::uint64_t> bits_;
};

}  // namespace exao
