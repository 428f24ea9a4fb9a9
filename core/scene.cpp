#include "core/scene.h"

#include "core/huge_pages.h"

#include <algorithm>
#include <cmath>

namespace exao {

Bounds Scene::bounds() const {
  Bounds b;
  const std::size_t model = vertices.size() - std::min(vertices.size(), 3 * ground_triangles);
  for (std::size_t i = 0; i < model; ++i) b.extend(vertices[i]);
  return b;
}

void Scene::reserve(std::size_t triangles) {
  reserve_huge(vertices, vertices.size() + 3 * triangles + kVertexPadding);
  reserve_huge(two_sided, two_sided.size() + triangles);
  reserve_huge(material, material.size() + triangles);
}

void apply_sidedness(Scene& scene, Sidedness sidedness) {
  if (sidedness == Sidedness::Auto) return;
  std::fill(scene.two_sided.begin(), scene.two_sided.end(), sidedness == Sidedness::Two ? 1 : 0);
}

std::size_t two_sided_count(const Scene& scene) {
  return static_cast<std::size_t>(std::count(scene.two_sided.begin(), scene.two_sided.end(), 1));
}

}  // namespace exao
