#pragma once
// exao::Cutouts: alpha-tested occluders (glTF alphaMode MASK: leaves, fences, grilles, decals)
// and the one function that decides whether such a triangle blocks a ray (DESIGN.md section 1).
//
// Every backend asks the same question in the same arithmetic: Embree's occlusion filter with the
// ray it casts, the masks with the same ray rebuilt from the same floats (origin p', direction
// Frame::to_world_direction of the pattern's direction), for the candidate bits of a cut-out
// triangle. The answer depends only on the stored floats, never on Embree's own u, v, so masks and
// rays agree on every ray that both find geometrically.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/enum_names.h"
#include "core/error.h"
#include "core/receiver_frame.h"
#include "core/shadow_rays.h"

namespace exao {

/// Texture wrapping (glTF sampler wrapS / wrapT).
enum class TextureWrap { Repeat, Clamp, Mirror };
/// Texture filtering at a hit: a ray has no footprint, so the sampler's magFilter applies (no
/// mip level); glTF leaves it undefined by default, and exao then filters linearly.
enum class TextureFilter { Nearest, Linear };

/// A texture's alpha channel as a cut-out reads it: width x height texels, row 0 at v = 0 (the
/// image's first row, glTF's convention), each alpha in [0, 65535] (8-bit images scaled by 257).
struct AlphaTexture {
  int width = 0;
  int height = 0;
  std::vector<std::uint16_t> alpha;  // width * height, row by row
  TextureFilter filter = TextureFilter::Linear;
  TextureWrap wrap_s = TextureWrap::Repeat;
  TextureWrap wrap_t = TextureWrap::Repeat;

  /// The alpha at (u, v) in [0, 1] per the filter and wrapping; NaN for a non-finite u or v.
  [[nodiscard]] double sample(double u, double v) const;
};

/// How a material's alpha decides a ray.
enum class AlphaRule {
  Opaque,      // blocks every ray it is hit by (as an OPAQUE material)
  Cutoff,      // blocks where alpha >= cutoff (MASK, or BLEND under BlendRule::Cutoff)
  Stochastic,  // blocks with probability alpha (BLEND under BlendRule::Stochastic)
};

struct CutoutMaterial {
  std::string name;        // the file's material name, for `exao info`
  bool blend = false;      // glTF BLEND (else MASK): its rule follows CutoutPolicy::blend
  float factor = 1.0f;     // baseColorFactor's alpha, clamped to [0, 1]
  float cutoff = 0.5f;     // alphaCutoff (MASK) or CutoutPolicy::blend_cutoff (BLEND)
  int texture = -1;        // index in Cutouts::textures, -1: none (alpha = factor x COLOR_0.a)
  AlphaRule rule = AlphaRule::Cutoff;
};

/// One alpha-tested triangle: its world vertices (the scene's floats), the UV of each corner in
/// the material texture's set with KHR_texture_transform applied, and COLOR_0's alpha.
struct CutoutTriangle {
  glm::vec3 v0{0.0f}, v1{0.0f}, v2{0.0f};
  glm::vec2 uv[3] = {glm::vec2(0.0f), glm::vec2(0.0f), glm::vec2(0.0f)};
  float color_alpha[3] = {1.0f, 1.0f, 1.0f};
  std::uint32_t material = 0;  // index in Cutouts::materials
};

/// What `--cutouts` and `--blend` choose: whether MASK materials cut out at all, and what BLEND
/// materials do (opaque by default; a cutoff at blend_cutoff; or a stochastic test).
enum class BlendRule { Opaque, Cutoff, Stochastic };

[[nodiscard]] constexpr auto enum_names(BlendRule) {
  return std::to_array<EnumName<BlendRule>>(
      {{BlendRule::Opaque, "opaque"}, {BlendRule::Cutoff, "cutoff"}, {BlendRule::Stochastic, "stochastic"}});
}

struct CutoutPolicy {
  bool enabled = true;                 // false: every triangle opaque, as before cut-outs
  BlendRule blend = BlendRule::Opaque;
  float blend_cutoff = 0.5f;           // with BlendRule::Cutoff; in [0, 1]
};

[[nodiscard]] const char* blend_rule_name(BlendRule rule);
/// "opaque", "cutoff" or "stochastic"; the error names the option "blend".
[[nodiscard]] Result<BlendRule> parse_blend_rule(const std::string& name);
/// Checks blend_cutoff (finite, in [0, 1]); the error names "blend_cutoff" and its value.
[[nodiscard]] Result<void> check_policy(const CutoutPolicy& policy);

struct Cutouts {
  std::vector<std::shared_ptr<const AlphaTexture>> textures;  // shared: copies keep the pixels once
  std::vector<CutoutMaterial> materials;
  std::vector<CutoutTriangle> triangles;
  /// Per scene triangle: its index in `triangles`, or -1 (opaque). Shorter than the scene (a
  /// ground plane added after loading): the rest are opaque.
  std::vector<std::int32_t> of_triangle;

  /// Whether scene triangle t is alpha-tested under the current rules (not Opaque).
  [[nodiscard]] bool tests(std::size_t t) const {
    if (t >= of_triangle.size() || of_triangle[t] < 0) return false;
    return materials[triangles[static_cast<std::size_t>(of_triangle[t])].material].rule != AlphaRule::Opaque;
  }
  /// Whether any triangle is alpha-tested.
  [[nodiscard]] bool any() const;
  /// Number of scene triangles alpha-tested.
  [[nodiscard]] std::size_t tested_count() const;

  /// baseColorFactor.a x texture alpha x COLOR_0.a of scene triangle t at barycentrics (b1, b2)
  /// (the weights of v1 and v2); 1 for an opaque triangle. NaN when the UV is not finite.
  [[nodiscard]] double alpha(std::size_t t, double b1, double b2) const;

  /// THE decision (DESIGN.md section 1): whether scene triangle t, hit by the ray origin +
  /// s * direction (the floats the caller casts), blocks it. Barycentrics come from the
  /// stored vertices in double (Moeller-Trumbore, clamped onto the triangle: a hit the caller
  /// found geometrically near an edge reads the edge's texels); a non-finite alpha (NaN UV)
  /// blocks, as an opaque triangle would. Stochastic: blocks iff a hash of the ray's floats and t
  /// (the floats are a function of the receiver key and ray index: every method hashes the same
  /// bits) falls below alpha. An opaque triangle blocks. Not inline: one compiled copy, the same
  /// bits whichever instruction set the caller's kernels use.
  [[nodiscard]] bool blocks(std::size_t t, const glm::vec3& origin, const glm::vec3& direction) const;

  /// The opacity a method that weighs occluders by it reads at the point where the ray origin +
  /// s * direction meets triangle t (exao compare's A-buffer): Cutoff 0 or 1, Stochastic (BLEND)
  /// the alpha itself, Opaque 1.
  [[nodiscard]] float opacity(std::size_t t, const glm::vec3& origin, const glm::vec3& direction) const;
};

/// The cut-outs under `policy`: nullptr when disabled or when no triangle is left alpha-tested
/// (so that an opaque scene takes the opaque code path), else a copy with the rules set (MASK:
/// Cutoff at its alphaCutoff; BLEND: per policy.blend). Textures are shared, not copied.
[[nodiscard]] std::shared_ptr<const Cutouts> apply_cutout_policy(const std::shared_ptr<const Cutouts>& cutouts,
                                                                 const CutoutPolicy& policy);

/// Whether apply_cutout_policy(cutouts, policy) would leave any triangle alpha-tested, without
/// the copy: a capability check before any work.
[[nodiscard]] bool cuts_out(const Cutouts* cutouts, const CutoutPolicy& policy);

/// Clears the bits of `mask` (row of `words` 64-bit words, bit i = ray i) whose ray cut-out
/// triangle t lets through: ray i is origin frame.origin, direction
/// frame.to_world_direction(rays.pattern.directions[i]), exactly the floats the Embree reference
/// casts. One call per candidate triangle with set bits; costs one decision per set bit.
void filter_cutout_rays(const Cutouts& cutouts, std::size_t t, const ShadowRays& rays, const Frame& frame,
                        std::span<std::uint64_t> mask);

}  // namespace exao
