#include "core/orientation.h"

#include <cmath>

namespace exao {
namespace {

// Shewchuk's o3derrboundA for epsilon = 2^-53: |computed - exact| <= bound * permanent.
constexpr double kEpsilon = 0x1p-53;
constexpr double kErrorBoundA = (7.0 + 56.0 * kEpsilon) * kEpsilon;

// a + b = sum + error exactly (Knuth's TwoSum; round to nearest, no fast-math).
inline void two_sum(double a, double b, double& sum, double& error) {
  sum = a + b;
  const double virtual_b = sum - a;
  const double virtual_a = sum - virtual_b;
  error = (a - virtual_a) + (b - virtual_b);
}

// Shewchuk's Grow-Expansion with zero elimination: e (count nonoverlapping components, smallest
// first) plus b, in place. e must have room for count + 1 components.
inline int grow_expansion(double* e, int count, double b) {
  double q = b;
  int out = 0;
  for (int i = 0; i < count; ++i) {
    double sum = 0.0, error = 0.0;
    two_sum(q, e[i], sum, error);
    q = sum;
    if (error != 0.0) e[out++] = error;
  }
  if (q != 0.0) e[out++] = q;
  return out;
}

// Adds +-x*y*z exactly: x*y of two floats is exact in double (48 significant bits), and
// (x*y)*z is split into its rounded value and the exact error by a fused multiply-add.
inline int add_product(double* e, int count, double sign, float x, float y, float z) {
  const double xy = sign * static_cast<double>(x) * static_cast<double>(y);
  const double p = xy * static_cast<double>(z);
  const double error = std::fma(xy, static_cast<double>(z), -p);
  count = grow_expansion(e, count, error);
  return grow_expansion(e, count, p);
}

// +-det(r0, r1, r2) of float rows, as 6 products into the expansion.
inline int add_det(double* e, int count, double sign, const glm::vec3& r0, const glm::vec3& r1, const glm::vec3& r2) {
  count = add_product(e, count, sign, r0.x, r1.y, r2.z);
  count = add_product(e, count, -sign, r0.x, r1.z, r2.y);
  count = add_product(e, count, sign, r0.y, r1.z, r2.x);
  count = add_product(e, count, -sign, r0.y, r1.x, r2.z);
  count = add_product(e, count, sign, r0.z, r1.x, r2.y);
  return add_product(e, count, -sign, r0.z, r1.y, r2.x);
}

// By multilinearity (terms with two rows equal to d vanish):
// det(a - d, b - d, c - d) = det(a, b, c) - det(d, b, c) - det(a, d, c) - det(a, b, d).
int exact_orientation(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
  double e[49];  // 48 terms: each grow adds at most one component
  int count = 0;
  count = add_det(e, count, 1.0, a, b, c);
  count = add_det(e, count, -1.0, d, b, c);
  count = add_det(e, count, -1.0, a, d, c);
  count = add_det(e, count, -1.0, a, b, d);
  // Nonoverlapping, increasing magnitude, no zeros: the last component carries the sign.
  if (count == 0) return 0;
  return e[count - 1] > 0.0 ? 1 : -1;
}

}  // namespace

int orientation(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
  // Shewchuk's orient3d stage A, with the differences rounded in double.
  const double adx = double(a.x) - double(d.x), ady = double(a.y) - double(d.y), adz = double(a.z) - double(d.z);
  const double bdx = double(b.x) - double(d.x), bdy = double(b.y) - double(d.y), bdz = double(b.z) - double(d.z);
  const double cdx = double(c.x) - double(d.x), cdy = double(c.y) - double(d.y), cdz = double(c.z) - double(d.z);
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                           (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                           (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
  const double bound = kErrorBoundA * permanent;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return exact_orientation(a, b, c, d);
}

}  // namespace exao
