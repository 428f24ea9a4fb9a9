#pragma once
// The receiver frame (DESIGN.md section 3): where a receiver's shadow rays start and how the
// shared pattern is oriented there. Every backend calls make_frame, so they cast the same rays.

#include <cstdint>

#include <glm/glm.hpp>

namespace exao {

/// An object id (Scene::object) that no triangle has: a receiver that excludes nothing.
inline constexpr std::uint32_t kNoObject = 0xFFFFFFFFu;

/// A point that receives occlusion.
struct Receiver {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // geometric normal; need not be unit, must be non-zero
  std::uint64_t key = 0;               // picks the jitter: pixel, vertex or texel index, or the caller's
  /// The triangles of this object (Scene::object) block none of its rays, in every backend: a
  /// renderer's "not the shaded object itself". kNoObject: every triangle may block.
  std::uint32_t excluded_object = kNoObject;
};

/// An orthonormal basis at the rays' origin. Local +Z is the (tilted) normal.
struct Frame {
  glm::vec3 origin{0.0f};  // p' = p + eps * n: where every ray starts
  glm::vec3 tangent{1.0f, 0.0f, 0.0f};
  glm::vec3 bitangent{0.0f, 1.0f, 0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};
  std::uint32_t excluded_object = kNoObject;  // the receiver's (Receiver::excluded_object)

  /// A world point in local coordinates (origin at p').
  [[nodiscard]] glm::vec3 to_local(const glm::vec3& world) const {
    const glm::vec3 d = world - origin;
    return {glm::dot(d, tangent), glm::dot(d, bitangent), glm::dot(d, normal)};
  }
  /// A local direction in world coordinates.
  [[nodiscard]] glm::vec3 to_world_direction(const glm::vec3& local) const {
    return local.x * tangent + local.y * bitangent + local.z * normal;
  }
};

/// Largest rotation of the tangent about the tilted normal, radians. Small, as the paper asks,
/// for coherence; large enough to break up banding on flat surfaces.
inline constexpr float kMaxFrameRotation = 0.3926991f;  // pi / 8

/// The frame of `receiver`: origin p + origin_offset * n^ (n^ = unit normal), normal n^ tilted
/// by a pseudo-random angle in [0, max_tilt) towards a pseudo-random azimuth, tangent rotated
/// about it by a pseudo-random angle in [-kMaxFrameRotation, kMaxFrameRotation]; all three from
/// a hash of receiver.key. max_tilt must stay below the pattern's smallest elevation so that no
/// ray dips below the true tangent plane (ShadowRays passes half of it).
[[nodiscard]] Frame make_frame(const Receiver& receiver, float origin_offset, float max_tilt);

/// Duff et al. 2017, "Building an Orthonormal Basis, Revisited": continuous except at n.z = -1.
void orthonormal_basis(const glm::vec3& n, glm::vec3& tangent, glm::vec3& bitangent);

}  // namespace exao
