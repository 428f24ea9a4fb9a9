#include "core/builtin_scenes.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/cutouts.h"

namespace exao {
namespace {

// A quad a, b, c, d, counter-clockwise seen from its front, split into an n x m grid of cells
// so that per-vertex bakes have vertices to hold the AO.
void add_grid(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 d, int n, int m, bool two_sided = false) {
  const glm::vec3 u = (b - a) / static_cast<float>(n);
  const glm::vec3 v = (d - a) / static_cast<float>(m);
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      const glm::vec3 p = a + static_cast<float>(i) * u + static_cast<float>(j) * v;
      scene.add_triangle(p, p + u, p + u + v, two_sided, 0);
      scene.add_triangle(p, p + u + v, p + v, two_sided, 0);
    }
  }
}

int cells(float length, float cell) { return std::max(1, static_cast<int>(std::lround(length / cell))); }

// A box from lo to hi; faces point outwards when `outward`, inwards (a room) otherwise.
void add_box(Scene& scene, glm::vec3 lo, glm::vec3 hi, bool outward, float cell) {
  const glm::vec3 e = hi - lo;
  struct Face { glm::vec3 a, b, d; };
  // Each face listed counter-clockwise as seen from outside the box.
  const Face faces[6] = {
      {{lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}},  // +Z
      {{hi.x, lo.y, lo.z}, {lo.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}},  // -Z
      {{hi.x, lo.y, hi.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}},  // +X
      {{lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, lo.z}},  // -X
      {{lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, lo.z}},  // +Y
      {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}},  // -Y
  };
  for (const Face& f : faces) {
    const float wu = glm::length(f.b - f.a);
    const float wv = glm::length(f.d - f.a);
    if (outward) {
      add_grid(scene, f.a, f.b, f.d, cells(wu, cell), cells(wv, cell));
    } else {
      add_grid(scene, f.a, f.d, f.b, cells(wv, cell), cells(wu, cell));  // swapped axes flip the winding
    }
  }
  (void)e;
}

void add_sphere(Scene& scene, glm::vec3 centre, float radius, int slices, int stacks) {
  const auto point = [&](int i, int j) {
    const float phi = 6.2831853f * static_cast<float>(i) / static_cast<float>(slices);
    const float theta = 3.1415927f * static_cast<float>(j) / static_cast<float>(stacks);
    return centre + radius * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
  };
  for (int j = 0; j < stacks; ++j) {
    for (int i = 0; i < slices; ++i) {
      const glm::vec3 a = point(i, j), b = point(i, j + 1), c = point(i + 1, j + 1), d = point(i + 1, j);
      if (j > 0) scene.add_triangle(a, b, d, false, 0);            // the poles have one triangle per slice
      if (j < stacks - 1) scene.add_triangle(d, b, c, false, 0);
    }
  }
}

// A checker of `cells` x `cells` squares, alternately opaque (alpha 1) and open (alpha 0), of
// `texels` x `texels` texels: the foliage scene's cards.
std::shared_ptr<const AlphaTexture> checker_texture(int texels, int cells, TextureFilter filter) {
  auto texture = std::make_shared<AlphaTexture>();
  texture->width = texture->height = texels;
  texture->filter = filter;
  texture->alpha.resize(static_cast<std::size_t>(texels) * static_cast<std::size_t>(texels));
  const int cell = std::max(1, texels / cells);
  for (int y = 0; y < texels; ++y) {
    for (int x = 0; x < texels; ++x) {
      texture->alpha[static_cast<std::size_t>(y * texels + x)] = ((x / cell + y / cell) % 2 == 0) ? 65535 : 0;
    }
  }
  return texture;
}

}  // namespace

void add_cutout_quad(Scene& scene, Cutouts& cutouts, const glm::vec3& a, const glm::vec3& b, const glm::vec3& d,
                     std::uint32_t material, bool two_sided) {
  const glm::vec3 c = b + d - a;
  const glm::vec2 ua(0.0f, 1.0f), ub(1.0f, 1.0f), uc(1.0f, 0.0f), ud(0.0f, 0.0f);
  const auto add = [&](const glm::vec3& p, const glm::vec3& q, const glm::vec3& r, glm::vec2 up, glm::vec2 uq,
                       glm::vec2 ur) {
    if (!scene.add_triangle(p, q, r, two_sided, static_cast<std::int32_t>(material))) return;
    cutouts.of_triangle.resize(scene.triangle_count(), -1);
    cutouts.of_triangle.back() = static_cast<std::int32_t>(cutouts.triangles.size());
    CutoutTriangle tri;
    tri.v0 = p, tri.v1 = q, tri.v2 = r;
    tri.uv[0] = up, tri.uv[1] = uq, tri.uv[2] = ur;
    tri.material = material;
    cutouts.triangles.push_back(tri);
  };
  add(a, b, c, ua, ub, uc);
  add(a, c, d, ua, uc, ud);
}

Scene make_foliage(bool cut_out) {
  Scene scene;
  scene.name = "foliage";
  // A 12 x 12 ground (one-sided, facing up), then 7 x 7 cards standing on it.
  add_grid(scene, {-6.0f, 0.0f, 6.0f}, {6.0f, 0.0f, 6.0f}, {-6.0f, 0.0f, -6.0f}, 24, 24);
  auto cutouts = std::make_shared<Cutouts>();
  cutouts->textures.push_back(checker_texture(32, 8, TextureFilter::Linear));
  CutoutMaterial leaves;
  leaves.name = "checker-cards";
  leaves.texture = 0;
  leaves.cutoff = 0.5f;
  cutouts->materials.push_back(leaves);
  cutouts->of_triangle.assign(scene.triangle_count(), -1);
  for (int j = 0; j < 7; ++j) {
    for (int i = 0; i < 7; ++i) {
      // A fixed pseudo-random yaw and lean per card (a golden-ratio sequence: no two alike).
      const float k = static_cast<float>(7 * j + i);
      const float yaw = 6.2831853f * std::fmod(0.618034f * k, 1.0f);
      const float lean = 0.35f * (std::fmod(0.414214f * k, 1.0f) - 0.5f);
      const glm::vec3 base(-4.5f + 1.5f * static_cast<float>(i), 0.05f, -4.5f + 1.5f * static_cast<float>(j));
      const glm::vec3 across = 0.6f * glm::vec3(std::cos(yaw), 0.0f, std::sin(yaw));
      const glm::vec3 facing(-std::sin(yaw), 0.0f, std::cos(yaw));
      const glm::vec3 up = 1.6f * glm::normalize(glm::vec3(0.0f, 1.0f, 0.0f) + lean * facing);
      add_cutout_quad(scene, *cutouts, base - across, base + across, base - across + up, 0, true);
    }
  }
  if (cut_out) scene.cutouts = std::move(cutouts);
  scene.cameras.push_back(look_at({-5.5f, 3.4f, 6.5f}, {0.3f, 0.4f, -0.6f}, 55.0f));
  scene.cameras.back().name = "field";
  return scene;
}

Scene make_room() {
  Scene scene;
  scene.name = "room";
  const float cell = 0.25f;
  add_box(scene, {-5.0f, 0.0f, -4.0f}, {5.0f, 4.0f, 4.0f}, false, cell);
  add_box(scene, {-2.6f, 0.0f, -1.8f}, {-0.4f, 1.0f, -0.4f}, true, cell);
  add_box(scene, {-2.2f, 1.0f, -1.5f}, {-1.4f, 1.8f, -0.7f}, true, cell);
  add_box(scene, {3.2f, 0.0f, -3.6f}, {3.8f, 4.0f, -3.0f}, true, cell);
  add_sphere(scene, {1.6f, 0.9f, 0.6f}, 0.9f, 48, 24);
  scene.cameras.push_back(look_at({-4.3f, 2.7f, 3.7f}, {0.8f, 0.7f, -1.4f}, 62.0f));
  scene.cameras.back().name = "inside";
  return scene;
}

Scene make_plane_pair(float height, float half_size) {
  Scene scene;
  scene.name = "plane-pair";
  const int n = cells(2.0f * half_size, 0.25f);
  const float s = half_size;
  add_grid(scene, {-s, 0.0f, s}, {s, 0.0f, s}, {-s, 0.0f, -s}, n, n);                // floor, facing +Y
  add_grid(scene, {-s, height, -s}, {s, height, -s}, {-s, height, s}, n, n);      // ceiling, facing -Y
  scene.cameras.push_back(look_at({-0.9f * s, 0.5f * height, 0.9f * s}, {0.0f, 0.0f, 0.0f}, 70.0f));
  scene.cameras.back().name = "between";
  return scene;
}

Scene make_sphere_on_plane() {
  Scene scene;
  scene.name = "sphere-on-plane";
  add_grid(scene, {-4.0f, 0.0f, 4.0f}, {4.0f, 0.0f, 4.0f}, {-4.0f, 0.0f, -4.0f}, 32, 32);
  add_sphere(scene, {0.0f, 1.0f, 0.0f}, 1.0f, 64, 32);
  return scene;
}

Scene make_hidden_box(bool box, bool wall) {
  Scene scene;
  scene.name = "hidden-box";
  add_grid(scene, {-6.0f, 0.0f, 6.0f}, {6.0f, 0.0f, 6.0f}, {-6.0f, 0.0f, -6.0f}, 48, 48);
  if (wall) add_box(scene, {0.1f, 0.0f, 2.0f}, {4.0f, 3.0f, 2.1f}, true, 0.25f);
  if (box) add_box(scene, {0.1f, 0.0f, -0.5f}, {1.1f, 1.0f, 0.5f}, true, 0.25f);
  scene.cameras.push_back(look_at({0.3f, 2.0f, 6.0f}, {-0.2f, 0.0f, 0.0f}, 50.0f));
  scene.cameras.back().name = "view";
  return scene;
}

Scene make_corners() {
  Scene scene;
  scene.name = "corners";
  // Every coordinate below is a multiple of 1/4, so each grid vertex is exact in float and lies
  // exactly in the planes it should: the cases of the surface rule happen, not nearly happen.
  add_grid(scene, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 4.0f}, {4.0f, 0.0f, 0.0f}, 16, 16);  // floor, facing +Y
  add_grid(scene, {0.0f, 0.0f, 0.0f}, {0.0f, 1.5f, 0.0f}, {0.0f, 0.0f, 4.0f}, 6, 16);   // wall x = 0, facing +X
  add_grid(scene, {0.0f, 0.0f, 0.0f}, {4.0f, 0.0f, 0.0f}, {0.0f, 1.5f, 0.0f}, 16, 6);   // wall z = 0, facing +Z
  // A box on the floor (its bottom face in the floor's plane) and one against the wall x = 0.
  add_box(scene, {1.0f, 0.0f, 1.0f}, {1.75f, 0.5f, 1.5f}, true, 0.25f);
  add_box(scene, {0.0f, 0.0f, 2.5f}, {0.5f, 0.75f, 3.25f}, true, 0.25f);
  // Two two-sided quads through each other: one upright (x = 2.75), one tilted at 45 degrees
  // (z = y + 0.75) standing on the floor; their vertices on the crossing line lie exactly in the
  // other quad's plane, the tilted one where Embree's own test is decided by rounding.
  add_grid(scene, {2.75f, 0.0f, 0.5f}, {2.75f, 0.0f, 2.0f}, {2.75f, 1.0f, 0.5f}, 6, 4, true);
  add_grid(scene, {2.0f, 0.0f, 0.75f}, {3.5f, 0.0f, 0.75f}, {2.0f, 1.0f, 1.75f}, 6, 4, true);
  scene.cameras.push_back(look_at({3.9f, 2.3f, 3.9f}, {1.2f, 0.3f, 1.2f}, 60.0f));
  scene.cameras.back().name = "corner";
  return scene;
}

std::vector<std::string> builtin_scene_names() { return {"room", "plane-pair", "sphere-on-plane", "hidden-box", "corners", "foliage"}; }

Result<Scene> builtin_scene(const std::string& name) {
  if (name == "room") return make_room();
  if (name == "plane-pair") return make_plane_pair();
  if (name == "sphere-on-plane") return make_sphere_on_plane();
  if (name == "hidden-box") return make_hidden_box();
  if (name == "corners") return make_corners();
  if (name == "foliage") return make_foliage();
  return fail(name + ": no such built-in scene (room, plane-pair, sphere-on-plane, hidden-box, corners, foliage)");
}

}  // namespace exao
