#include "bake/dilate.h"

#include <vector>

namespace exao::bake {

void dilate(std::span<float> values, std::span<std::uint8_t> filled, int width, int height, int margin,
            float background) {
  std::vector<std::size_t> ring;
  std::vector<float> ring_values;
  for (int pass = 0; pass < margin; ++pass) {
    ring.clear();
    ring_values.clear();
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
        if (filled[i]) continue;
        float sum = 0.0f;
        int count = 0;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
            const std::size_t j = static_cast<std::size_t>(ny) * static_cast<std::size_t>(width) + static_cast<std::size_t>(nx);
            if (filled[j]) {
              sum += values[j];
              ++count;
            }
          }
        }
        if (count > 0) {
          ring.push_back(i);
          ring_values.push_back(sum / static_cast<float>(count));
        }
      }
    }
    if (ring.empty()) break;
    // A ring reads only the texels filled before it, so the result does not depend on scan order.
    for (std::size_t r = 0; r < ring.size(); ++r) {
      values[ring[r]] = ring_values[r];
      filled[ring[r]] = 2;
    }
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!filled[i]) values[i] = background;
  }
}

}  // namespace exao::bake
