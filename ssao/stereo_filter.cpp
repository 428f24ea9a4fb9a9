#include "ssao/stereo_filter.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include <tbb/parallel_for.h>

#include "ssao/stereo_hbao_plus.h"

namespace exao::ssao {
namespace {

struct Offset {
  int dx, dy;
};

// F and W of view `v` over the neighbourhood of pixel c (offsets), centred at world point P
// with sigma: sum O G and sum G. W = 0 when no neighbour holds a surface.
void filter_at(const View& v, const std::vector<float>& in, std::size_t c, const glm::dvec3& P, double inverse_two_sigma_sq,
               const std::vector<Offset>& offsets, double& F, double& W) {
  const int cx = static_cast<int>(c % static_cast<std::size_t>(v.width)), cy = static_cast<int>(c / static_cast<std::size_t>(v.width));
  double sum = 0.0, weight = 0.0;
  for (const Offset& o : offsets) {
    const int x = cx + o.dx, y = cy + o.dy;
    if (x < 0 || y < 0 || x >= v.width || y >= v.height) continue;
    const std::size_t k = static_cast<std::size_t>(y) * static_cast<std::size_t>(v.width) + static_cast<std::size_t>(x);
    if (!v.valid[k]) continue;
    const glm::dvec3 d = glm::dvec3(v.position[k]) - P;
    // G's constant 1 / (sqrt(2 pi) sigma) is the same for both eyes (one sigma per P): it
    // cancels in F and in alpha.
    const double g = std::exp(-glm::dot(d, d) * inverse_two_sigma_sq);
    sum += g * in[k];
    weight += g;
  }
  W = weight;
  F = weight > 0.0 ? sum / weight : 0.0;
}

// One stereo filter pass: out^v(p) = w F^v(p) + (1 - w) F^other(p*) for both eyes.
void pass(const std::array<const View*, 2>& views, const std::array<const std::vector<float>*, 2>& in,
          const std::array<std::vector<float>*, 2>& out, const std::vector<Offset>& offsets, int footprint, double eta) {
  for (int e = 0; e < 2; ++e) {
    const View& v = *views[static_cast<std::size_t>(e)];
    const View& other = *views[static_cast<std::size_t>(1 - e)];
    const std::vector<float>& own_in = *in[static_cast<std::size_t>(e)];
    const std::vector<float>& other_in = *in[static_cast<std::size_t>(1 - e)];
    std::vector<float>& result = *out[static_cast<std::size_t>(e)];
    tbb::parallel_for(std::size_t{0}, v.pixel_count(), [&](std::size_t p) {
      result[p] = own_in[p];
      if (!v.valid[p]) return;
      const glm::dvec3 P(v.position[p]);
      // sigma = l / 3, l the world length of the N-pixel footprint at P's depth.
      const double sigma = footprint / v.pixels_per_unit(v.depth[p]) / 3.0;
      const double inverse_two_sigma_sq = 1.0 / (2.0 * sigma * sigma);
      double F = 0.0, W = 0.0;
      filter_at(v, own_in, p, P, inverse_two_sigma_sq, offsets, F, W);
      const std::int64_t q = nearest_pixel(other, P);
      double F_other = 0.0, W_other = 0.0;
      if (q >= 0) filter_at(other, other_in, static_cast<std::size_t>(q), P, inverse_two_sigma_sq, offsets, F_other, W_other);
      const double w = W_other > 0.0 ? stereo_filter_weight(W / (W + W_other), eta) : 1.0;
      result[p] = static_cast<float>(w * F + (1.0 - w) * F_other);
    });
  }
}

}  // namespace

double stereo_filter_weight(double alpha, double eta) {
  // GLSL smoothstep(0.5 - eta, 0.5, alpha).
  const double t = std::clamp((alpha - (0.5 - eta)) / eta, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

void stereo_filter(const View& left, const View& right, std::vector<float>& left_ao, std::vector<float>& right_ao,
                   const StereoFilterOptions& options) {
  assert(left.width == right.width && left.height == right.height);
  const int r = options.radius;
  if (r <= 0) return;
  const int footprint = 2 * r + 1;
  const std::array<const View*, 2> views{&left, &right};
  std::vector<float> left_temp(left_ao.size()), right_temp(right_ao.size());
  if (options.form == StereoFilterForm::Full) {
    std::vector<Offset> square;
    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) square.push_back({dx, dy});
    }
    pass(views, {&left_ao, &right_ao}, {&left_temp, &right_temp}, square, footprint, options.eta);
  } else {
    std::vector<Offset> row, column;
    for (int k = -r; k <= r; ++k) {
      row.push_back({k, 0});
      column.push_back({0, k});
    }
    std::vector<float> left_x(left_ao.size()), right_x(right_ao.size());
    pass(views, {&left_ao, &right_ao}, {&left_x, &right_x}, row, footprint, options.eta);
    pass(views, {&left_x, &right_x}, {&left_temp, &right_temp}, column, footprint, options.eta);
  }
  left_ao.swap(left_temp);
  right_ao.swap(right_temp);
}

}  // namespace exao::ssao
