#pragma once
// The one key for welding vertices by position (the bake's corner normals and glTF conversion,
// the box atlas, the raster level of detail): the bits of x, y and z with -0.0 made +0.0, so
// that two positions that compare equal as floats have equal keys and equal hashes (hashing
// raw float bits while comparing with == would break unordered_map's contract at -0.0).

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

namespace exao {

struct PositionKey {
  std::array<std::uint32_t, 3> bits{};
  bool operator==(const PositionKey&) const = default;
};

/// The key of `p`. Adding +0.0 turns -0.0 into +0.0 and leaves every other value as it is.
[[nodiscard]] inline PositionKey position_key(const glm::vec3& p) {
  const glm::vec3 u = p + glm::vec3(0.0f);
  return {{std::bit_cast<std::uint32_t>(u.x), std::bit_cast<std::uint32_t>(u.y), std::bit_cast<std::uint32_t>(u.z)}};
}

/// FNV-1a over the key's three words: for std::unordered_map<PositionKey, T, PositionKeyHash>.
struct PositionKeyHash {
  [[nodiscard]] std::size_t operator()(const PositionKey& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (const std::uint32_t b : k.bits) h = (h ^ b) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

}  // namespace exao
