// exao::api::load_scene and the library's version and status texts.

#include <string>
#include <vector>

#include "api/boundary.h"
#include "io/load_scene.h"
#include "core/scene.h"
#include "exao/exao.hpp"

namespace exao::api {

static_assert(kVersionMajor == EXAO_VERSION_MAJOR && kVersionMinor == EXAO_VERSION_MINOR && kVersionPatch == EXAO_VERSION_PATCH,
              "include/exao/exao.hpp's kVersion* must equal project(exao VERSION ...) in CMakeLists.txt");

#define EXAO_STRINGIFY_(x) #x
#define EXAO_STRINGIFY(x) EXAO_STRINGIFY_(x)

const char* version() noexcept {
  return EXAO_STRINGIFY(EXAO_VERSION_MAJOR) "." EXAO_STRINGIFY(EXAO_VERSION_MINOR) "." EXAO_STRINGIFY(EXAO_VERSION_PATCH);
}

const char* status_text(StatusCode code) noexcept {
  switch (code) {
    case StatusCode::Ok: return "ok";
    case StatusCode::InvalidArgument: return "invalid argument";
    case StatusCode::OutOfMemory: return "out of memory";
    case StatusCode::FileError: return "file error";
    case StatusCode::BackendError: return "backend error";
    case StatusCode::InternalError: return "internal error";
    case StatusCode::Cancelled: return "cancelled";
    case StatusCode::CallbackError: return "callback error";
  }
  return "unknown status";
}

namespace {

Vec3 to_vec3(const glm::vec3& v) { return {v.x, v.y, v.z}; }

}  // namespace

Result<SceneData> load_scene(std::string_view name_or_path) noexcept {
  return detail::guard<Result<SceneData>>([&]() -> Result<SceneData> {
    if (name_or_path.empty()) return detail::invalid("name_or_path: empty");
    exao::Result<Scene> scene = open_scene(std::string(name_or_path));
    if (!scene) return detail::from_internal(StatusCode::FileError, scene.error());
    SceneData out;
    out.name = scene->name;
    out.positions.resize(3 * scene->vertices.size());
    for (std::size_t i = 0; i < scene->vertices.size(); ++i) {
      out.positions[3 * i + 0] = scene->vertices[i].x;
      out.positions[3 * i + 1] = scene->vertices[i].y;
      out.positions[3 * i + 2] = scene->vertices[i].z;
    }
    out.two_sided = std::move(scene->two_sided);
    out.material = std::move(scene->material);
    for (const exao::Camera& c : scene->cameras) {
      out.cameras.push_back(Camera{c.name, to_vec3(c.eye), to_vec3(c.forward), to_vec3(c.up), c.yfov, c.aspect.value_or(0.0f)});
    }
    const LoadReport& r = scene->report;
    if (r.zero_area_skipped) {
      out.notes.push_back("skipped " + std::to_string(r.zero_area_skipped) + " zero-area triangles of " + std::to_string(r.triangles_read));
    }
    if (r.non_finite_skipped) {
      out.notes.push_back("skipped " + std::to_string(r.non_finite_skipped) + " triangles with NaN or infinite vertices");
    }
    for (const std::string& note : r.notes) out.notes.push_back(note);
    return out;
  });
}

std::vector<std::string> builtin_scene_names() noexcept {
  try {
    return exao::builtin_scene_names();
  } catch (...) {
    return {};
  }
}

}  // namespace exao::api
