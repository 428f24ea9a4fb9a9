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

// Every (texel, triangle) pair the conservative raster gives, texel by texel (stable within one).
std::vector<Candidate> texel_candidates(std::span<const UvTriangle> triangles, int width, int height) {
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    rasterize_conservative(triangles[i].uv, width, height, [&](int x, int y) {
      candidates.push_back({static_cast<std::uint32_t>(y * width + x), static_cast<std::uint32_t>(i)});
    });
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.texel < b.texel; });
  return candidates;
}

// Receivers in the order they are made, each with the next key.
struct ReceiverSink {
  TexelReceivers& out;
  std::uint64_t key;
  void add(Receiver r, std::uint32_t texel) {
    r.key = key++;
    out.receivers.push_back(r);
    out.texel.push_back(texel);
  }
};

// The receivers of sample point `p` of `texel`, among its candidates: every triangle that holds
// it strictly when two or more overlap there (returns true; a few such pairs of source triangles
// go into `examples`), else the triangle that holds it deepest.
bool sample_receivers(std::span<const UvTriangle> triangles, std::span<const Candidate> candidates, const glm::dvec2& p,
                      std::uint32_t texel, ReceiverSink& sink, std::set<std::array<std::uint32_t, 2>>& examples,
                      std::vector<std::uint32_t>& strict) {
  double best_depth = -std::numeric_limits<double>::infinity();
  std::uint32_t best = 0;
  glm::dvec3 best_b(0.0);
  strict.clear();
  for (const Candidate& c : candidates) {
    const UvTriangle& t = triangles[c.triangle];
    const glm::dvec3 b = barycentric(t.uv, p);
    const double depth = std::min({b.x, b.y, b.z});
    if (depth >= kInside && depth > best_depth) {
      best_depth = depth;
      best = c.triangle;
      best_b = b;
    }
    if (depth > kOverlap) strict.push_back(c.triangle);
  }
  Receiver r;
  if (strict.size() >= 2) {
    for (const std::uint32_t t : strict) {
      if (make_receiver(triangles[t], barycentric(triangles[t].uv, p), r)) sink.add(r, texel);
      const std::uint32_t a = triangles[strict[0]].source, b = triangles[t].source;
      if (t != strict[0] && examples.size() < kMaxOverlapExamples) examples.insert({std::min(a, b), std::max(a, b)});
    }
    return true;
  }
  if (best_depth >= kInside && make_receiver(triangles[best], best_b, r)) sink.add(r, texel);
  return false;
}

// A texel only partly covered: the closest point of its triangles to the texel centre.
void closest_receiver(std::span<const UvTriangle> triangles, std::span<const Candidate> candidates,
                      const glm::dvec2& centre, std::uint32_t texel, ReceiverSink& sink) {
  double best_d2 = std::numeric_limits<double>::infinity();
  std::uint32_t best = 0;
  glm::dvec3 best_b(0.0);
  for (const Candidate& c : candidates) {
    double d2 = 0.0;
    const glm::dvec3 b = closest_barycentric(triangles[c.triangle].uv, centre, d2);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = c.triangle;
      best_b = b;
    }
  }
  Receiver r;
  if (make_receiver(triangles[best], best_b, r)) sink.add(r, texel);
}

}  // namespace

TexelReceivers texel_receivers(std::span<const UvTriangle> triangles, int width, int height, int samples_per_side,
                               std::uint64_t first_key) {
  TexelReceivers out;
  const std::size_t texel_count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  out.covered.assign(texel_count, 0);
  const std::vector<Candidate> candidates = texel_candidates(triangles, width, height);
  const int k = std::max(1, samples_per_side);
  std::set<std::array<std::uint32_t, 2>> examples;
  ReceiverSink sink{out, first_key};
  std::vector<std::uint32_t> strict;
  for (std::size_t begin = 0; begin < candidates.size();) {
    std::size_t end = begin;
    const std::uint32_t texel = candidates[begin].texel;
    while (end < candidates.size() && candidates[end].texel == texel) ++end;
    const std::span<const Candidate> mine(candidates.data() + begin, end - begin);
    const double x = texel % static_cast<std::uint32_t>(width), y = texel / static_cast<std::uint32_t>(width);
    const std::size_t before = out.receivers.size();
    bool overlap = false;
    for (int j = 0; j < k; ++j) {
      for (int i = 0; i < k; ++i) {
        const glm::dvec2 p(x + (i + 0.5) / k, y + (j + 0.5) / k);
        overlap |= sample_receivers(triangles, mine, p, texel, sink, examples, strict);
      }
    }
    if (out.receivers.size() == before) closest_receiver(triangles, mine, glm::dvec2(x + 0.5, y + 0.5), texel, sink);
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
