#include "bake/texel_receivers.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace exao::bake {
namespace {

// A sample counts as inside down to this barycentric (a relative measure): samples on a shared
// edge belong to one of its triangles even after rounding.
constexpr double kInside = -1e-9;
// Deeper than this in two triangles is an overlap, not two triangles meeting along an edge.
constexpr double kOverlap = 1e-4;
constexpr std::size_t kMaxOverlapExamples = 8;

struct Candidate {
  std::uint32_t texel;
  std::uint32_t triangle;
};

bool make_receiver(const UvTriangle& t, const glm::dvec3& b, Receiver& out) {
  const glm::dvec3 p = b.x * glm::dvec3(t.position[0]) + b.y * glm::dvec3(t.position[1]) + b.z * glm::dvec3(t.position[2]);
  glm::dvec3 n = b.x * glm::dvec3(t.normal[0]) + b.y * glm::dvec3(t.normal[1]) + b.z * glm::dvec3(t.normal[2]);
  // Opposite corner normals can cancel; the face normal is the receiver's normal then.
  if (!(glm::length(n) > 1e-6)) {
    n = glm::cross(glm::dvec3(t.position[1]) - glm::dvec3(t.position[0]),
                   glm::dvec3(t.position[2]) - glm::dvec3(t.position[0]));
  }
  const double length = glm::length(n);
  if (!(length > 0.0) || !std::isfinite(length)) return false;
  out.position = glm::vec3(p);
  out.normal = glm::vec3(n / length);
  return true;
}

}  // namespace

TexelReceivers texel_receivers(std::span<const UvTriangle> triangles, int width, int height, int samples_per_side,
                               std::uint64_t first_key) {
  TexelReceivers out;
  const std::size_t texel_count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  out.covered.assign(texel_count, 0);
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    rasterize_conservative(triangles[i].uv, width, height, [&](int x, int y) {
      candidates.push_back({static_cast<std::uint32_t>(y * width + x), static_cast<std::uint32_t>(i)});
    });
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.texel < b.texel; });

  const int k = std::max(1, samples_per_side);
  std::set<std::array<std::uint32_t, 2>> examples;
  std::uint64_t key = first_key;
  std::vector<std::uint32_t> strict;
  for (std::size_t begin = 0; begin < candidates.size();) {
    std::size_t end = begin;
    const std::uint32_t texel = candidates[begin].texel;
    while (end < candidates.size() && candidates[end].texel == texel) ++end;
    const double x = texel % static_cast<std::uint32_t>(width), y = texel / static_cast<std::uint32_t>(width);
    const std::size_t before = out.receivers.size();
    bool overlap = false;
    for (int j = 0; j < k; ++j) {
      for (int i = 0; i < k; ++i) {
        const glm::dvec2 p(x + (i + 0.5) / k, y + (j + 0.5) / k);
        double best_depth = -std::numeric_limits<double>::infinity();
        std::uint32_t best = 0;
        glm::dvec3 best_b(0.0);
        strict.clear();
        for (std::size_t c = begin; c < end; ++c) {
          const UvTriangle& t = triangles[candidates[c].triangle];
          const glm::dvec3 b = barycentric(t.uv, p);
          const double depth = std::min({b.x, b.y, b.z});
          if (depth >= kInside && depth > best_depth) {
            best_depth = depth;
            best = candidates[c].triangle;
            best_b = b;
          }
          if (depth > kOverlap) strict.push_back(candidates[c].triangle);
        }
        Receiver r;
        if (strict.size() >= 2) {
          overlap = true;
          for (const std::uint32_t t : strict) {
            if (make_receiver(triangles[t], barycentric(triangles[t].uv, p), r)) {
              r.key = key++;
              out.receivers.push_back(r);
              out.texel.push_back(texel);
            }
            const std::uint32_t a = triangles[strict[0]].source, b = triangles[t].source;
            if (t != strict[0] && examples.size() < kMaxOverlapExamples) examples.insert({std::min(a, b), std::max(a, b)});
          }
        } else if (best_depth >= kInside && make_receiver(triangles[best], best_b, r)) {
          r.key = key++;
          out.receivers.push_back(r);
          out.texel.push_back(texel);
        }
      }
    }
    if (out.receivers.size() == before) {
      // Only partly covered: the closest point of its triangles to the texel centre.
      const glm::dvec2 centre(x + 0.5, y + 0.5);
      double best_d2 = std::numeric_limits<double>::infinity();
      std::uint32_t best = 0;
      glm::dvec3 best_b(0.0);
      for (std::size_t c = begin; c < end; ++c) {
        double d2 = 0.0;
        const glm::dvec3 b = closest_barycentric(triangles[candidates[c].triangle].uv, centre, d2);
        if (d2 < best_d2) {
          best_d2 = d2;
          best = candidates[c].triangle;
          best_b = b;
        }
      }
      Receiver r;
      if (make_receiver(triangles[best], best_b, r)) {
        r.key = key++;
        out.receivers.push_back(r);
        out.texel.push_back(texel);
      }
    }
    if (out.receivers.size() > before) {
      out.covered[texel] = 1;
      ++out.covered_texels;
      if (overlap) ++out.overlap_texels;
    }
    begin = end;
  }
  out.overlap_examples.assign(examples.begin(), examples.end());
  return out;
}

}  // namespace exao::bake
