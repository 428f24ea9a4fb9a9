#pragma once
// The Embree reference ray caster (DESIGN.md section 5, `embree`): the ground truth every other
// backend is checked against, and the speed it must beat, so it runs at its best.

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include <glm/glm.hpp>

#include "core/enum_names.h"
#include "core/error.h"
#include "core/mask_set.h"
#include "core/progress.h"
#include "core/scene.h"
#include "core/shadow_rays.h"

namespace exao {

/// How Embree is asked about the rays: one at a time, or in packets of 4, 8 or 16.
enum class EmbreeRays { Single, Packet4, Packet8, Packet16 };

[[nodiscard]] constexpr auto enum_names(EmbreeRays) {
  return std::to_array<EnumName<EmbreeRays>>({{EmbreeRays::Single, "single"},
                                              {EmbreeRays::Packet4, "packet4"},
                                              {EmbreeRays::Packet8, "packet8"},
                                              {EmbreeRays::Packet16, "packet16"}});
}

[[nodiscard]] const char* embree_rays_name(EmbreeRays rays);
[[nodiscard]] Result<EmbreeRays> parse_embree_rays(const std::string& name);

struct EmbreeOptions {
  /// The default, 16-wide packets of one sample of 16 neighbouring receivers, was the fastest on
  /// room and Conference, N = 128 and 1024, on the AVX-512 machine exao is developed on (about
  /// 2x single rays; `exao bench --embree-rays single,packet4,packet8,packet16` measures it).
  EmbreeRays rays = EmbreeRays::Packet16;
  /// Packets hold the same sample of neighbouring receivers (near-parallel rays from nearby
  /// origins) rather than neighbouring samples of one receiver (rays fanning out from a point).
  bool across_receivers = true;
  /// RTC_INTERSECT_CONTEXT_FLAG_COHERENT for packets. Off: Embree 3.13.5 then traverses a
  /// packet by one frustum (kernels/bvh/node_intersector_frustum.h, Frustum<false>), whose node
  /// tests round org * rdir for the whole packet and can cull a node that one lane's ray clearly
  /// hits (a Conference vertex receiver's ray that hits a wall 0.05 units away, in the middle of
  /// the triangle, came out open in a packet and blocked alone). The reference must give every
  /// ray the answer it gets alone; and on the bakes' receivers incoherent packets were faster.
  bool coherent = false;
};

/// A scene committed to Embree. One-sided and two-sided triangles live in two geometries; the
/// occlusion filter of both rejects hits on a triangle whose plane the ray origin lies on
/// (the surface rule, core/surface_rule.h), and the one-sided geometry's also rejects back-face
/// hits. Immutable after build; any number of threads may query it at once. Uses the TBB thread
/// limit in force (tbb::global_control).
class EmbreeScene {
 public:
  struct Hit {
    std::uint32_t triangle;  // index into Scene's triangles
    float distance;          // along the unit ray direction
  };

  /// Embree reads a copy of the scene's vertices (36 bytes a triangle); the scene need not
  /// outlive the result.
  /// `progress` gets Embree's own estimate of its build (rtcSetSceneProgressMonitorFunction), in
  /// thousandths.
  [[nodiscard]] static Result<EmbreeScene> build(const Scene& scene, const ProgressCallback& progress = {});
  /// The same scene, with Embree reading `scene.vertices` in place (rtcSetSharedGeometryBuffer):
  /// no copy. The vector's storage must then outlive the result where it is (moving the vector
  /// keeps it; growing or freeing it does not), changed only as refit says. Embree reads each
  /// vertex with a 16-byte load, so the vector needs spare capacity for Scene::kVertexPadding
  /// more vertices; without it the vertices are copied as build(scene) copies them
  /// (shares_vertices() says which). The same rays, the same answers.
  [[nodiscard]] static Result<EmbreeScene> build_sharing(const Scene& scene, const ProgressCallback& progress = {});
  /// Whether Embree reads the caller's vertices (build_sharing with the padding there).
  [[nodiscard]] bool shares_vertices() const;
  /// Moves the triangles of the scene build was given to `vertices` (3 per triangle, the
  /// scene's order; sidedness and objects kept) and refits Embree's BVH
  /// (RTC_BUILD_QUALITY_REFIT): no rebuild. Not while any thread queries this scene. A scene
  /// that shares the caller's vertices takes that same array, already moved (an error otherwise).
  [[nodiscard]] Result<void> refit(std::span<const glm::vec3> vertices);
  EmbreeScene(EmbreeScene&&) noexcept;
  EmbreeScene& operator=(EmbreeScene&&) noexcept;
  ~EmbreeScene();

  /// Nearest hit of either face of any triangle along origin + t * direction, t in [0, inf).
  [[nodiscard]] std::optional<Hit> closest_hit(const glm::vec3& origin, const glm::vec3& direction) const;

  /// Casts the N rays of every receiver (DESIGN.md section 1) and returns their masks, in the
  /// receivers' order. Multithreaded with TBB; progress is reported in receivers.
  [[nodiscard]] MaskSet occlusion(const ShadowRays& rays, std::span<const Receiver> receivers,
                                  const EmbreeOptions& options = {},
                                  const ProgressCallback& progress = {}) const;

  /// Casts only the rays the caller asks for: for receiver k (frame frames[k]), ray i iff bit i
  /// of row k of `wanted` is set, each row `words` words; ORs the occluded ones into the same
  /// bits of `blocked` (same layout). The rays are occlusion()'s own (same origin, direction and
  /// length floats), in incoherent packets of 16 lanes across neighbouring receivers, one sample
  /// at a time; so each gets the answer occlusion() gives it. On the calling thread, no
  /// allocation; call it inside a lut::FlushDenormals-like float mode or not: it sets its own.
  /// Returns the number of rays cast.
  std::size_t occlude_selected(const ShadowRays& rays, std::span<const Frame> frames,
                               std::span<const std::uint64_t> wanted, std::size_t words,
                               std::span<std::uint64_t> blocked) const;

 struct Impl;  // opaque: Embree's headers stay out of exao's

 private:
  [[nodiscard]] static Result<EmbreeScene> build(const Scene& scene, bool share, const ProgressCallback& progress);
  explicit EmbreeScene(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace exao
