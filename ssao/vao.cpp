#include "ssao/vao.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <string>

#include <tbb/parallel_for.h>

namespace exao::ssao {
namespace {

constexpr double kPsi[kVaoSamples] = {1.0 / 16, 9.0 / 16, 5.0 / 16, 13.0 / 16, 3.0 / 16, 11.0 / 16, 7.0 / 16, 15.0 / 16};

}  // namespace

Result<void> check(const VaoOptions& options) {
  if (!(options.thickness >= 0.0 && options.thickness <= 1.0)) {
    return fail("thickness: must be in [0, 1], got " + std::to_string(options.thickness));
  }
  return {};
}

double column_z(const View& view, const Settings& settings, std::size_t p, const glm::dvec3& point) {
  const glm::dvec3 P(view.position[p]);
  const glm::dvec3 e = glm::normalize(view.eye - P);
  return glm::dot(point - P, e) / settings.radius;
}

double surface_z(const View& view, const Settings& settings, std::size_t p, const VaoSample& sample, std::size_t q) {
  const glm::dvec3 P(view.position[p]);
  const glm::dvec3 e = glm::normalize(view.eye - P);
  const glm::dvec3 S(view.position[q]), m(view.normal[q]);
  const double along = glm::dot(e, m);
  const double fallback = column_z(view, settings, p, S);
  if (!(std::abs(along) > 1e-6)) return fallback;
  const double z = glm::dot(S - sample.point, m) / (settings.radius * along);
  return std::isfinite(z) ? z : fallback;
}

VaoSample vao_sample(const View& view, const Settings& settings, std::size_t p, int i) {
  VaoSample s;
  const glm::dvec3 P(view.position[p]);
  const glm::dvec3 n(view.normal[p]);
  const glm::dvec3 e = glm::normalize(view.eye - P);
  // A basis of the disc facing the eye (Duff et al. 2017).
  const double sign = std::copysign(1.0, e.z);
  const double a = -1.0 / (sign + e.z), b = e.x * e.y * a;
  const glm::dvec3 u(1.0 + sign * e.x * e.x * a, sign * b, -sign * e.x);
  const glm::dvec3 v(b, sign + e.y * e.y * a, -e.y);
  // Seed 001's Eq. 4 rotates the samples by a per-pixel xi without giving its range; the
  // authors' public code rotates by noise x 2 pi, and only a full turn is unbiased: sample i's
  // angle is then uniform, and its column cut by a plane through P at angle theta and at
  // theta + pi add up to the whole column, so each sample's expected share is exactly 1/2 on an
  // open plane (with xi in [0, 2 pi / 8) each sample stays in its own 45-degree sector, and a
  // tilted open plane averages 0.95-1.05). Over a 4 x 4 block xi takes 16 equally spaced values,
  // so the angles theta and theta + pi both occur: the block's mean is 1 up to perspective.
  const double angle = 2.0 * std::numbers::pi * (static_cast<double>(i) / kVaoSamples + block_jitter(p, view.width, 2));
  const double rho = std::sqrt(1.0 - std::pow(kPsi[i], 2.0 / 3.0));
  const glm::dvec3 offset = settings.radius * rho * (std::cos(angle) * u + std::sin(angle) * v);
  s.height = 2.0 * std::sqrt(1.0 - rho * rho);
  s.point = P + offset;
  const double facing = glm::dot(e, n);
  if (!(facing > 1e-6)) return s;
  const double z_plane = -glm::dot(offset, n) / (settings.radius * facing);
  s.z_lo = std::max(-0.5 * s.height, z_plane);
  s.z_hi = 0.5 * s.height;
  s.valid = s.z_lo < s.z_hi;
  s.pixel = view.pixel_at(view.project(P + offset));
  return s;
}

double unoccupied(const VaoSample& s, double z, double thickness) {
  const double length = s.z_hi - s.z_lo;
  if (z <= s.z_lo) return length;
  if (z <= s.z_hi) return s.z_hi - z;
  const double front = 1.0 + thickness;  // end of the constant area
  if (z <= front) return 0.0;
  return std::min(z - front, length);
}

VaoResult vao(const View& view, const Settings& settings, const VaoOptions& options) {
  VaoResult out;
  const std::size_t n = view.pixel_count();
  out.ao.assign(n, 1.0f);
  out.unflagged.assign(n, 1.0f);
  out.flags.assign(n, 0);
  out.stencil.assign(n, 0);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t p) {
    if (!view.valid[p]) return;
    // HBAO's guards (ssao/horizon_march.h), which seed 001 leaves open: a ball that projects to
    // less than a pixel has no neighbour to read, so the pixel is open, as HBAO+ does.
    if (settings.radius * view.pixels_per_unit(view.depth[p]) < 1.0) return;
    double all = 0.0, unflagged = 0.0;
    std::uint8_t flags = 0;
    for (int i = 0; i < kVaoSamples; ++i) {
      const VaoSample s = vao_sample(view, settings, p, i);
      if (!s.valid) continue;
      // Off screen, background, or the receiver's own pixel: nothing in the column above the
      // tangent plane. The own pixel's depth is the receiver itself (z = 0), not the surface
      // under the sample point, so reading it would cut every column whose plane part lies
      // below the receiver at z = 0 and darken open surfaces whenever r projects to a few pixels
      // (an open floor at r = 0.05 averaged 0.89); HBAO skips its own pixel the same way.
      double u = s.z_hi - s.z_lo;
      if (s.pixel >= 0 && static_cast<std::size_t>(s.pixel) != p && view.valid[static_cast<std::size_t>(s.pixel)]) {
        const double z = surface_z(view, settings, p, s, static_cast<std::size_t>(s.pixel));
        u = unoccupied(s, z, options.thickness);
        if (z > 1.0 + options.thickness) {
          flags = static_cast<std::uint8_t>(flags | (1u << i));
          // Several pixels may mark the same one, from different threads.
          std::atomic_ref<std::uint8_t>(out.stencil[static_cast<std::size_t>(s.pixel)]).store(1, std::memory_order_relaxed);
        }
      }
      all += u / s.height;
      if (!(flags & (1u << i))) unflagged += u / s.height;
    }
    out.ao[p] = static_cast<float>(2.0 * all / kVaoSamples);
    out.unflagged[p] = static_cast<float>(2.0 * unflagged / kVaoSamples);
    out.flags[p] = flags;
  });
  return out;
}

}  // namespace exao::ssao
