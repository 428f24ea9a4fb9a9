#include "core/cutouts.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace exao {
namespace {

// Texel index i (any integer, as a double: UVs may be huge) wrapped into [0, n).
double wrap_index(double i, int n, TextureWrap wrap) {
  const double size = static_cast<double>(n);
  switch (wrap) {
    case TextureWrap::Clamp: return std::clamp(i, 0.0, size - 1.0);
    case TextureWrap::Repeat: {
      const double m = std::fmod(i, size);
      return m < 0.0 ? m + size : m;
    }
    case TextureWrap::Mirror: {
      double m = std::fmod(i, 2.0 * size);
      if (m < 0.0) m += 2.0 * size;
      return m < size ? m : 2.0 * size - 1.0 - m;
    }
  }
  return 0.0;
}

// splitmix64's finaliser: every input bit reaches every output bit.
std::uint64_t mix(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ull;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Uniform in [0, 1) from the ray's floats and the triangle (see Cutouts::blocks).
double ray_hash01(std::size_t t, const glm::vec3& o, const glm::vec3& d) {
  std::uint64_t h = mix(static_cast<std::uint64_t>(t) + 0x9e3779b97f4a7c15ull);
  for (const float f : {o.x, o.y, o.z, d.x, d.y, d.z}) h = mix(h ^ std::bit_cast<std::uint32_t>(f));
  return static_cast<double>(h >> 11) * 0x1p-53;
}

// Barycentrics (b1, b2) of the point where origin + s * direction meets the triangle's plane,
// Moeller-Trumbore in double, clamped onto the triangle; the centroid for a ray in its plane.
void barycentrics(const CutoutTriangle& tri, const glm::vec3& origin, const glm::vec3& direction, double& b1,
                  double& b2) {
  const glm::dvec3 v0(tri.v0), e1 = glm::dvec3(tri.v1) - v0, e2 = glm::dvec3(tri.v2) - v0;
  const glm::dvec3 d(direction);
  const glm::dvec3 p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  b1 = b2 = 1.0 / 3.0;
  if (!(std::abs(det) > 0.0) || !std::isfinite(det)) return;
  const glm::dvec3 s = glm::dvec3(origin) - v0;
  const glm::dvec3 q = glm::cross(s, e1);
  const double u = glm::dot(s, p) / det, v = glm::dot(d, q) / det;
  if (!(std::isfinite(u) && std::isfinite(v))) return;
  b1 = std::max(u, 0.0);
  b2 = std::max(v, 0.0);
  if (b1 + b2 > 1.0) {
    const double sum = b1 + b2;
    b1 /= sum;
    b2 /= sum;
  }
}

}  // namespace

double AlphaTexture::sample(double u, double v) const {
  if (!(std::isfinite(u) && std::isfinite(v))) return std::nan("");
  if (width <= 0 || height <= 0) return 1.0;
  const auto texel = [&](double x, double y) {
    const auto i = static_cast<std::size_t>(wrap_index(x, width, wrap_s));
    const auto j = static_cast<std::size_t>(wrap_index(y, height, wrap_t));
    return static_cast<double>(alpha[j * static_cast<std::size_t>(width) + i]) / 65535.0;
  };
  const double x = u * width, y = v * height;
  if (filter == TextureFilter::Nearest) return texel(std::floor(x), std::floor(y));
  // Linear: texel centres at integer + 0.5.
  const double fx = x - 0.5, fy = y - 0.5;
  const double x0 = std::floor(fx), y0 = std::floor(fy);
  const double ax = fx - x0, ay = fy - y0;
  const double top = (1.0 - ax) * texel(x0, y0) + ax * texel(x0 + 1.0, y0);
  const double bottom = (1.0 - ax) * texel(x0, y0 + 1.0) + ax * texel(x0 + 1.0, y0 + 1.0);
  return (1.0 - ay) * top + ay * bottom;
}

const char* blend_rule_name(BlendRule rule) { return name_of(rule); }

Result<BlendRule> parse_blend_rule(const std::string& name) {
  if (const std::optional<BlendRule> r = parse_enum<BlendRule>(name)) return *r;
  return fail("blend: unknown rule '" + name + "' (" + name_list<BlendRule>() + ")");
}

Result<void> check_policy(const CutoutPolicy& policy) {
  if (!(policy.blend_cutoff >= 0.0f && policy.blend_cutoff <= 1.0f)) {
    return fail("blend_cutoff: must be in [0, 1], got " + detail::short_number(policy.blend_cutoff));
  }
  return {};
}

bool Cutouts::any() const {
  for (std::size_t t = 0; t < of_triangle.size(); ++t) {
    if (tests(t)) return true;
  }
  return false;
}

std::size_t Cutouts::tested_count() const {
  std::size_t n = 0;
  for (std::size_t t = 0; t < of_triangle.size(); ++t) n += tests(t) ? 1 : 0;
  return n;
}

double Cutouts::alpha(std::size_t t, double b1, double b2) const {
  if (t >= of_triangle.size() || of_triangle[t] < 0) return 1.0;
  const CutoutTriangle& tri = triangles[static_cast<std::size_t>(of_triangle[t])];
  const CutoutMaterial& material = materials[tri.material];
  const double b0 = 1.0 - b1 - b2;
  double a = static_cast<double>(material.factor);
  a *= b0 * tri.color_alpha[0] + b1 * tri.color_alpha[1] + b2 * tri.color_alpha[2];
  if (material.texture >= 0) {
    const double u = b0 * tri.uv[0].x + b1 * tri.uv[1].x + b2 * tri.uv[2].x;
    const double v = b0 * tri.uv[0].y + b1 * tri.uv[1].y + b2 * tri.uv[2].y;
    a *= textures[static_cast<std::size_t>(material.texture)]->sample(u, v);
  }
  return a;
}

bool Cutouts::blocks(std::size_t t, const glm::vec3& origin, const glm::vec3& direction) const {
  if (t >= of_triangle.size() || of_triangle[t] < 0) return true;
  const CutoutTriangle& tri = triangles[static_cast<std::size_t>(of_triangle[t])];
  const AlphaRule rule = materials[tri.material].rule;
  if (rule == AlphaRule::Opaque) return true;
  double b1 = 0.0, b2 = 0.0;
  barycentrics(tri, origin, direction, b1, b2);
  const double a = alpha(t, b1, b2);
  if (std::isnan(a)) return true;
  if (rule == AlphaRule::Stochastic) return ray_hash01(t, origin, direction) < a;
  return a >= static_cast<double>(materials[tri.material].cutoff);
}

float Cutouts::opacity(std::size_t t, const glm::vec3& origin, const glm::vec3& direction) const {
  if (t >= of_triangle.size() || of_triangle[t] < 0) return 1.0f;
  const CutoutTriangle& tri = triangles[static_cast<std::size_t>(of_triangle[t])];
  const CutoutMaterial& material = materials[tri.material];
  if (material.rule == AlphaRule::Opaque) return 1.0f;
  double b1 = 0.0, b2 = 0.0;
  barycentrics(tri, origin, direction, b1, b2);
  const double a = alpha(t, b1, b2);
  if (std::isnan(a)) return 1.0f;
  if (material.rule == AlphaRule::Stochastic) return static_cast<float>(std::clamp(a, 0.0, 1.0));
  return a >= static_cast<double>(material.cutoff) ? 1.0f : 0.0f;
}

namespace {

AlphaRule rule_under(const CutoutMaterial& m, const CutoutPolicy& policy) {
  if (!m.blend) return AlphaRule::Cutoff;
  switch (policy.blend) {
    case BlendRule::Opaque: return AlphaRule::Opaque;
    case BlendRule::Cutoff: return AlphaRule::Cutoff;
    case BlendRule::Stochastic: return AlphaRule::Stochastic;
  }
  return AlphaRule::Opaque;
}

}  // namespace

bool cuts_out(const Cutouts* cutouts, const CutoutPolicy& policy) {
  if (!cutouts || !policy.enabled) return false;
  std::vector<bool> tested(cutouts->materials.size());
  for (std::size_t m = 0; m < tested.size(); ++m) tested[m] = rule_under(cutouts->materials[m], policy) != AlphaRule::Opaque;
  for (const std::int32_t k : cutouts->of_triangle) {
    if (k >= 0 && tested[cutouts->triangles[static_cast<std::size_t>(k)].material]) return true;
  }
  return false;
}

std::shared_ptr<const Cutouts> apply_cutout_policy(const std::shared_ptr<const Cutouts>& cutouts,
                                                   const CutoutPolicy& policy) {
  if (!cutouts || !policy.enabled) return nullptr;
  auto out = std::make_shared<Cutouts>(*cutouts);
  for (CutoutMaterial& m : out->materials) {
    m.rule = rule_under(m, policy);
    if (m.blend && m.rule == AlphaRule::Cutoff) m.cutoff = policy.blend_cutoff;
  }
  if (!out->any()) return nullptr;
  return out;
}

void filter_cutout_rays(const Cutouts& cutouts, std::size_t t, const ShadowRays& rays, const Frame& frame,
                        std::span<std::uint64_t> mask) {
  const int n = rays.count();
  for (std::size_t w = 0; w < mask.size(); ++w) {
    for (std::uint64_t bits = mask[w]; bits; bits &= bits - 1) {
      const int i = static_cast<int>(64 * w) + std::countr_zero(bits);
      if (i >= n) break;
      if (!cutouts.blocks(t, frame.origin, rays.world_direction(frame, i))) mask[w] &= ~(std::uint64_t{1} << (i % 64));
    }
  }
}

}  // namespace exao
