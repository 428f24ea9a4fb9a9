#include "core/sample_pattern.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <tuple>
#include <numeric>
#include <sstream>

#include "core/atomic_write.h"
#include "core/check.h"
#include "core/random.h"

namespace exao {
namespace {

constexpr int kLloydSteps = 40;

// Lloyd relaxation on the unit disc, with the disc represented by many fixed density points:
// a Voronoi cell's centroid is the mean of the density points nearest its site. A uniform
// grid over the sites makes the nearest-site search cheap.
class DiscLloyd {
 public:
  DiscLloyd(int sites, Rng& rng) : sites_(static_cast<std::size_t>(sites)) {
    // Jittered-grid density points inside the disc, about 128 per site (at least 16K): enough
    // that a cell's centroid is within a small fraction of the site spacing of the true one.
    const int per_side =
        static_cast<int>(std::ceil(std::sqrt(std::max(16384.0, 128.0 * sites) * 4.0 / M_PI)));
    const double h = 2.0 / per_side;
    for (int j = 0; j < per_side; ++j) {
      for (int i = 0; i < per_side; ++i) {
        const glm::dvec2 p(-1.0 + (i + rng.uniform()) * h, -1.0 + (j + rng.uniform()) * h);
        if (glm::dot(p, p) < 1.0) density_.push_back(p);
      }
    }
    owner_.resize(density_.size());
    cell_ = 1.5 * std::sqrt(M_PI / sites);
    grid_side_ = static_cast<int>(std::ceil(2.0 / cell_));
  }

  // One Lloyd step: every site moves to the centroid of its cell.
  void relax(std::vector<glm::dvec2>& sites) {
    assign(sites);
    std::vector<glm::dvec2> sum(sites.size(), glm::dvec2(0.0));
    std::vector<int> count(sites.size(), 0);
    for (std::size_t k = 0; k < density_.size(); ++k) {
      sum[owner_[k]] += density_[k];
      ++count[owner_[k]];
    }
    for (std::size_t s = 0; s < sites.size(); ++s) {
      if (count[s] > 0) sites[s] = sum[s] / static_cast<double>(count[s]);
    }
  }

  // Moves every site to a random density point of its own cell: a random point of the cell.
  void jitter(std::vector<glm::dvec2>& sites, Rng& rng) {
    assign(sites);
    std::vector<std::vector<std::uint32_t>> members(sites.size());
    for (std::size_t k = 0; k < density_.size(); ++k) members[owner_[k]].push_back(static_cast<std::uint32_t>(k));
    for (std::size_t s = 0; s < sites.size(); ++s) {
      if (!members[s].empty()) sites[s] = density_[members[s][rng.below(static_cast<std::uint32_t>(members[s].size()))]];
    }
  }

 private:
  [[nodiscard]] int grid_index(double x) const {
    return std::clamp(static_cast<int>((x + 1.0) / cell_), 0, grid_side_ - 1);
  }

  void assign(const std::vector<glm::dvec2>& sites) {
    std::vector<std::vector<std::uint32_t>> grid(static_cast<std::size_t>(grid_side_ * grid_side_));
    for (std::size_t s = 0; s < sites.size(); ++s) {
      grid[grid_index(sites[s].y) * grid_side_ + grid_index(sites[s].x)].push_back(static_cast<std::uint32_t>(s));
    }
    for (std::size_t k = 0; k < density_.size(); ++k) {
      const glm::dvec2 p = density_[k];
      const int gx = grid_index(p.x);
      const int gy = grid_index(p.y);
      double best = INFINITY;
      std::uint32_t best_site = 0;
      // Search rings of cells outwards until no unvisited cell can hold a nearer site: every
      // cell of ring k+1 is at least k cells away.
      for (int ring = 0; ring <= grid_side_; ++ring) {
        const double reach = (ring - 1) * cell_;
        if (ring > 0 && reach > 0.0 && reach * reach > best) break;
        for (int y = gy - ring; y <= gy + ring; ++y) {
          if (y < 0 || y >= grid_side_) continue;
          for (int x = gx - ring; x <= gx + ring; ++x) {
            if (x < 0 || x >= grid_side_) continue;
            if (std::max(std::abs(x - gx), std::abs(y - gy)) != ring) continue;
            for (const std::uint32_t s : grid[y * grid_side_ + x]) {
              const glm::dvec2 d = sites[s] - p;
              const double dist = glm::dot(d, d);
              if (dist < best || (dist == best && s < best_site)) {
                best = dist;
                best_site = s;
              }
            }
          }
        }
      }
      owner_[k] = best_site;
    }
  }

  std::size_t sites_;
  std::vector<glm::dvec2> density_;
  std::vector<std::uint32_t> owner_;
  double cell_ = 1.0;
  int grid_side_ = 1;
};

// N random points, one in each of N equal-area strata. Lloyd relaxation fixes local spacing in a
// few steps but needs on the order of N steps to even out density across the disc, so points
// placed independently at random stay unbalanced (quadrant counts off by 15% at N = 256).
// The strata are the cells of a sunflower spiral (radius sqrt((k + 1/2) / N), golden-angle
// turns): each point is its spiral position, the spiral turned by a random angle, moved by a
// random offset of up to half the spacing.
std::vector<glm::dvec2> random_balanced_sites(int count, Rng& rng) {
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  const double spacing = std::sqrt(M_PI / count);
  const double turn = 2.0 * M_PI * rng.uniform();
  std::vector<glm::dvec2> sites;
  for (int k = 0; k < count; ++k) {
    const double radius = std::sqrt((k + 0.5) / count);
    const double angle = turn + k * golden_angle;
    glm::dvec2 p = radius * glm::dvec2(std::cos(angle), std::sin(angle));
    const double jitter_angle = 2.0 * M_PI * rng.uniform();
    const double jitter = 0.5 * spacing * std::sqrt(rng.uniform());
    p += jitter * glm::dvec2(std::cos(jitter_angle), std::sin(jitter_angle));
    if (glm::dot(p, p) >= 1.0) p *= 0.999 / glm::length(p);
    sites.push_back(p);
  }
  return sites;
}

// Inverse CDF of the ray length l / r for a falloff: P(l >= D) = rho(D), so that a shadow ray
// of length l is blocked by an occluder at distance D with probability rho(D) (Eq. 3 = Eq. 2).
float length_from_level(Falloff falloff, double u) {
  switch (falloff) {
    case Falloff::Constant: return 1.0f;
    case Falloff::Linear: return static_cast<float>(u);                              // rho = 1 - D
    case Falloff::Quadratic: return static_cast<float>(1.0 - std::sqrt(1.0 - u));    // rho = (1 - D)^2
  }
  return 1.0f;
}

// A relaxed pattern keeps its outermost ring about half a spacing inside the rim, so it has no
// ray within ~20 degrees of the horizon at N = 128, and a horizon-limited occluder (a ceiling at
// height h) is under-counted by up to (h/r)^2. Re-spacing the radii, in their own order, to
// stratified levels of r^2 makes the radial distribution exactly the cosine-weighted one (to 1/N)
// and keeps the angular arrangement the relaxation produced.
void equalise_radii(std::vector<glm::dvec2>& sites, Rng& rng) {
  std::vector<std::size_t> order(sites.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const double ra = glm::dot(sites[a], sites[a]), rb = glm::dot(sites[b], sites[b]);
    return ra < rb || (ra == rb && a < b);
  });
  const double n = static_cast<double>(sites.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    glm::dvec2& s = sites[order[k]];
    const double level = (static_cast<double>(k) + rng.uniform()) / n;  // stratified r^2 in [0, 1)
    const double length = glm::length(s);
    s = length > 0.0 ? s * (std::sqrt(level) / length) : glm::dvec2(std::sqrt(level), 0.0);
  }
}

// Sample i's ray is bit i of every mask, and the mask kernels evaluate samples in groups of
// kSampleCluster consecutive ones, each skipped when its bounding cone cannot reach a triangle
// or a sphere (lut/sample_clusters.h). So the order matters for speed only, never for the
// answer: recursive bisection of the directions along their widest axis, down to groups of
// kSampleCluster, makes each group a compact cone.
void bisect_into_clusters(std::vector<int>& index, std::size_t first, std::size_t count,
                          const std::vector<glm::vec3>& directions) {
  if (count <= static_cast<std::size_t>(kSampleCluster)) return;
  glm::vec3 lo(2.0f), hi(-2.0f);
  for (std::size_t k = first; k < first + count; ++k) {
    lo = glm::min(lo, directions[index[k]]);
    hi = glm::max(hi, directions[index[k]]);
  }
  const glm::vec3 extent = hi - lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  // Split at a whole number of clusters, as evenly as possible.
  const std::size_t clusters = count / kSampleCluster;
  const std::size_t left = (clusters / 2) * kSampleCluster;
  const auto begin = index.begin() + static_cast<std::ptrdiff_t>(first);
  std::nth_element(begin, begin + static_cast<std::ptrdiff_t>(left), begin + static_cast<std::ptrdiff_t>(count),
                   [&](int a, int b) {
                     const float ka = directions[a][axis], kb = directions[b][axis];
                     return ka < kb || (ka == kb && a < b);
                   });
  bisect_into_clusters(index, first, left, directions);
  bisect_into_clusters(index, first + left, count - left, directions);
}

void order_into_clusters(SamplePattern& pattern) {
  std::vector<int> index(pattern.directions.size());
  std::iota(index.begin(), index.end(), 0);
  bisect_into_clusters(index, 0, index.size(), pattern.directions);
  std::vector<glm::vec3> directions;
  std::vector<float> lengths;
  for (const int i : index) {
    directions.push_back(pattern.directions[i]);
    lengths.push_back(pattern.lengths[i]);
  }
  pattern.directions = std::move(directions);
  pattern.lengths = std::move(lengths);
}

void finish(SamplePattern& pattern) {
  pattern.points.resize(pattern.directions.size());
  float min_z = 1.0f;
  for (std::size_t i = 0; i < pattern.directions.size(); ++i) {
    pattern.points[i] = pattern.directions[i] * pattern.lengths[i];
    min_z = std::min(min_z, pattern.directions[i].z);
  }
  pattern.min_elevation = std::asin(min_z);
}

}  // namespace

const char* falloff_name(Falloff falloff) { return name_of(falloff); }

Result<Falloff> parse_falloff(const std::string& name) {
  if (const std::optional<Falloff> f = parse_enum<Falloff>(name)) return *f;
  return fail("falloff: unknown falloff '" + name + "' (" + name_list<Falloff>() + ")");
}

Result<void> check_sample_count(int count) {
  if (count < kMinSamples || count > kMaxSamples || count % 32 != 0) {
    return fail("samples: must be a multiple of 32 from 32 to 1024, got " + std::to_string(count));
  }
  return {};
}

Result<SamplePattern> make_sample_pattern(int count, Falloff falloff, std::uint64_t seed) {
  if (auto ok = check_sample_count(count); !ok) return std::unexpected(ok.error());
  // Building a pattern takes a good fraction of a second at N = 1024; a process that asks for
  // the same one again (bench, tests, a renderer with several engines) gets the first copy.
  static std::mutex cache_mutex;
  static std::map<std::tuple<int, Falloff, std::uint64_t>, SamplePattern> cache;
  const auto key = std::make_tuple(count, falloff, seed);
  {
    std::lock_guard lock(cache_mutex);
    if (const auto found = cache.find(key); found != cache.end()) return found->second;
  }
  SamplePattern pattern = build_sample_pattern(count, falloff, seed);
  std::lock_guard lock(cache_mutex);
  cache.emplace(key, pattern);
  return pattern;
}

SamplePattern build_sample_pattern(int count, Falloff falloff, std::uint64_t seed) {
  EXAO_CHECK(check_sample_count(count).has_value());
  Rng rng(mix64(seed) ^ static_cast<std::uint64_t>(count));

  DiscLloyd lloyd(count, rng);
  std::vector<glm::dvec2> sites = random_balanced_sites(count, rng);
  // Many steps to reach a semi-regular pattern, then randomness back in, then a few steps
  // more (paper Sec. 6): uniform density overall, with local randomness against aliasing.
  for (int step = 0; step < kLloydSteps; ++step) lloyd.relax(sites);
  lloyd.jitter(sites, rng);
  for (int step = 0; step < 3; ++step) lloyd.relax(sites);
  equalise_radii(sites, rng);

  SamplePattern pattern;
  pattern.count = count;
  pattern.falloff = falloff;
  pattern.seed = seed;
  for (const glm::dvec2& s : sites) {
    const double z = std::sqrt(std::max(0.0, 1.0 - glm::dot(s, s)));
    pattern.directions.push_back(glm::normalize(glm::vec3(glm::dvec3(s, z))));
  }
  // Stratified levels, one per stratum [k/N, (k+1)/N), given to the directions in random order.
  std::vector<int> strata(static_cast<std::size_t>(count));
  std::iota(strata.begin(), strata.end(), 0);
  for (int i = count - 1; i > 0; --i) std::swap(strata[i], strata[rng.below(static_cast<std::uint32_t>(i + 1))]);
  for (int i = 0; i < count; ++i) {
    // 1 - level keeps lengths in (0, 1]: a zero-length ray could never be blocked.
    const double level = 1.0 - (strata[i] + rng.uniform()) / count;
    pattern.lengths.push_back(std::max(length_from_level(falloff, level), 1e-6f));
  }
  order_into_clusters(pattern);
  finish(pattern);
  return pattern;
}

Result<SamplePattern> make_given_pattern(std::span<const glm::vec3> directions, std::span<const float> lengths) {
  const int count = static_cast<int>(std::min<std::size_t>(directions.size(), 1u << 20));
  if (auto ok = check_sample_count(count); !ok) {
    return fail("directions: N must be a multiple of 32 from 32 to 1024, got " + std::to_string(directions.size()));
  }
  if (!lengths.empty() && lengths.size() != directions.size()) {
    return fail("lengths: must be empty (all 1) or hold one per direction (" + std::to_string(directions.size()) +
                "), holds " + std::to_string(lengths.size()));
  }
  SamplePattern pattern;
  pattern.count = count;
  pattern.falloff = Falloff::Constant;  // the lengths are the caller's; only the table's cache reads it
  pattern.seed = 0;
  for (int i = 0; i < count; ++i) {
    const glm::vec3 d = directions[static_cast<std::size_t>(i)];
    const float length2 = glm::dot(d, d);
    if (!(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z) && std::isfinite(length2) && length2 > 0.0f)) {
      return fail("directions[" + std::to_string(i) + "]: must be finite and non-zero");
    }
    const glm::vec3 unit = glm::normalize(d);
    if (!(unit.z > 0.0f)) {
      return fail("directions[" + std::to_string(i) + "]: z must be > 0 (above the tangent plane), got " +
                  std::to_string(d.z));
    }
    const float length = lengths.empty() ? 1.0f : lengths[static_cast<std::size_t>(i)];
    if (!(length > 0.0f && length <= 1.0f)) {
      return fail("lengths[" + std::to_string(i) + "]: must be in (0, 1], got " + std::to_string(length));
    }
    pattern.directions.push_back(unit);
    pattern.lengths.push_back(length);
  }
  finish(pattern);
  return pattern;
}

Result<void> save_sample_pattern(const SamplePattern& pattern, const std::string& path) {
  std::ostringstream out;
  out << "exao-sample-pattern 1\n"
      << "samples " << pattern.count << "\nfalloff " << falloff_name(pattern.falloff)
      << "\nseed " << pattern.seed << "\n";
  out.precision(9);  // 9 significant digits give back every float exactly
  for (int i = 0; i < pattern.count; ++i) {
    const glm::vec3 d = pattern.directions[i];
    out << d.x << ' ' << d.y << ' ' << d.z << ' ' << pattern.lengths[i] << '\n';
  }
  return write_file_atomically(path, out.str());
}

Result<SamplePattern> load_sample_pattern(const std::string& path) {
  std::ifstream in(path);
  if (!in) return fail(path + ": cannot open");
  std::string magic, key_samples, key_falloff, key_seed, falloff;
  int version = 0;
  SamplePattern pattern;
  in >> magic >> version >> key_samples >> pattern.count >> key_falloff >> falloff >> key_seed >> pattern.seed;
  if (!in || magic != "exao-sample-pattern" || key_samples != "samples" || key_falloff != "falloff" ||
      key_seed != "seed") {
    return fail(path + ": not an exao sample pattern (bad header)");
  }
  if (version != 1) return fail(path + ": sample pattern format version " + std::to_string(version) + " is not supported");
  if (auto ok = check_sample_count(pattern.count); !ok) return fail(path + ": " + ok.error().message);
  auto parsed = parse_falloff(falloff);
  if (!parsed) return fail(path + ": " + parsed.error().message);
  pattern.falloff = *parsed;
  for (int i = 0; i < pattern.count; ++i) {
    glm::vec3 d;
    float length = 0.0f;
    if (!(in >> d.x >> d.y >> d.z >> length)) {
      return fail(path + ": sample " + std::to_string(i) + " is missing or malformed");
    }
    if (!(std::abs(glm::length(d) - 1.0f) < 1e-4f) || !(d.z > 0.0f) || !(length > 0.0f && length <= 1.0f)) {
      return fail(path + ": sample " + std::to_string(i) + " is not a unit direction above the horizon with length in (0, 1]");
    }
    pattern.directions.push_back(d);
    pattern.lengths.push_back(length);
  }
  std::string extra;
  if (in >> extra) return fail(path + ": unexpected data after " + std::to_string(pattern.count) + " samples");
  finish(pattern);
  return pattern;
}

}  // namespace exao
