#pragma once
// Receivers for a camera image (DESIGN.md section 3, issue "camera and pixel receivers"): the
// point where each pixel-centre ray meets the visible triangle, with that triangle's geometric
// normal turned toward the camera. The key of a pixel's receiver is its index y * width + x.

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/embree_reference.h"
#include "core/receiver_frame.h"
#include "core/scene.h"

namespace exao {

struct PixelReceivers {
  int width = 0;
  int height = 0;
  std::vector<Receiver> receivers;      // one per pixel that sees a triangle, in pixel order
  std::vector<std::uint32_t> pixel;     // pixel index of each receiver
  std::vector<std::uint32_t> triangle;  // visible triangle of each receiver
};

/// Primary visibility by Embree (either face of every triangle is visible).
[[nodiscard]] PixelReceivers pixel_receivers(const EmbreeScene& embree, const Scene& scene, const Camera& camera,
                                             int width, int height);

/// The receiver of a pixel whose centre ray hits `triangle` at distance `distance`.
[[nodiscard]] Receiver pixel_receiver(const Scene& scene, const Camera& camera, int width, int height,
                                      std::uint32_t pixel, std::uint32_t triangle, float distance);

}  // namespace exao
