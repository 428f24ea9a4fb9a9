#pragma once
// What every fuzz target asserts beyond "no crash": the loaders' contract (io/load_scene.h).
// A broken contract aborts, so AFL++ records the input as a crash.

#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/coordinate_limit.h"
#include "core/error.h"
#include "core/scene.h"

namespace exao::fuzz {

/// A refusal is one line naming the file.
inline void check_error(const Error& error, const std::string& path) {
  if (error.message.find('\n') != std::string::npos || error.message.find(path) == std::string::npos) {
    std::fprintf(stderr, "broken error contract for %s: '%s'\n", path.c_str(), error.message.c_str());
    std::abort();
  }
}

/// A loaded scene holds triangles, every vertex within the coordinate limit.
inline void check_scene(const Result<Scene>& scene, const std::string& path) {
  if (!scene) return check_error(scene.error(), path);
  if (scene->triangle_count() == 0 || scene->vertices.size() != 3 * scene->triangle_count()) std::abort();
  for (const glm::vec3& v : scene->vertices) {
    if (!within_coordinate_limit(v)) std::abort();
  }
}

}  // namespace exao::fuzz
