#include "core/receiver_frame.h"

#include <cmath>

#include "core/random.h"

namespace exao {

void orthonormal_basis(const glm::vec3& n, glm::vec3& tangent, glm::vec3& bitangent) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  tangent = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
  bitangent = {b, sign + n.y * n.y * a, -n.y};
}

Frame make_frame(const Receiver& receiver, float origin_offset, float max_tilt) {
  const glm::vec3 n = glm::normalize(receiver.normal);
  const std::uint64_t h0 = mix64(receiver.key ^ 0xA0C1u);
  const std::uint64_t h1 = mix64(h0);
  const std::uint64_t h2 = mix64(h1);
  const float tilt = max_tilt * unit_float(h0);
  const float azimuth = 6.28318531f * unit_float(h1);
  const float rotation = kMaxFrameRotation * (2.0f * unit_float(h2) - 1.0f);

  glm::vec3 t0, b0;
  orthonormal_basis(n, t0, b0);
  const glm::vec3 towards = std::cos(azimuth) * t0 + std::sin(azimuth) * b0;
  const glm::vec3 tilted = glm::normalize(std::cos(tilt) * n + std::sin(tilt) * towards);

  Frame frame;
  frame.origin = receiver.position + origin_offset * n;
  frame.normal = tilted;
  glm::vec3 t1, b1;
  orthonormal_basis(tilted, t1, b1);
  frame.tangent = std::cos(rotation) * t1 + std::sin(rotation) * b1;
  frame.bitangent = glm::cross(frame.normal, frame.tangent);
  frame.excluded_object = receiver.excluded_object;
  return frame;
}

}  // namespace exao
