// The C API (exao/exao.h): thin wrappers over exao::api::Engine. Each function converts its
// plain-C arguments, calls the C++ API and turns its Result into a status code; the message of a
// failed query is kept per thread (like errno), so that concurrent queries never see each
// other's messages, and a query that succeeds clears it.

#include "exao/exao.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <mutex>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "exao/exao.hpp"

using exao::api::Engine;
using exao::api::Error;
using exao::api::StatusCode;

struct exao_engine {
  explicit exao_engine(Engine built) : engine(std::move(built)) {}
  Engine engine;
};

namespace {

static_assert(static_cast<int>(StatusCode::Ok) == EXAO_OK && static_cast<int>(StatusCode::InvalidArgument) == EXAO_INVALID_ARGUMENT &&
              static_cast<int>(StatusCode::OutOfMemory) == EXAO_OUT_OF_MEMORY && static_cast<int>(StatusCode::FileError) == EXAO_FILE_ERROR &&
              static_cast<int>(StatusCode::BackendError) == EXAO_BACKEND_ERROR &&
              static_cast<int>(StatusCode::InternalError) == EXAO_INTERNAL_ERROR &&
              static_cast<int>(StatusCode::Cancelled) == EXAO_CANCELLED &&
              static_cast<int>(StatusCode::CallbackError) == EXAO_CALLBACK_ERROR);
static_assert(sizeof(exao_receiver) == sizeof(exao::api::Receiver));

exao_status to_c(StatusCode code) { return static_cast<exao_status>(static_cast<int>(code)); }

// Copies `message` into a caller's buffer, truncated and NUL-terminated; returns its length.
std::size_t copy_message(const std::string& message, char* buffer, std::size_t size) {
  if (buffer && size > 0) {
    const std::size_t n = std::min(message.size(), size - 1);
    std::memcpy(buffer, message.data(), n);
    buffer[n] = '\0';
  }
  return message.size();
}

// This thread's most recent query: on which engine, and its message when it failed ("" when it
// succeeded).
struct LastQuery {
  const exao_engine* engine = nullptr;
  std::string message;
};
thread_local LastQuery t_last;

// Records a failed query's message (best effort: a failed allocation leaves it empty) and
// returns its status.
exao_status record(const exao_engine* engine, StatusCode code, const std::string& message) {
  t_last.engine = engine;
  t_last.message.clear();
  try {
    t_last.message = message;
  } catch (...) {
  }
  return to_c(code);
}

exao_status record(const exao_engine* engine, const Error& error) { return record(engine, error.code, error.message); }

exao_status record(const exao_engine* engine, StatusCode code, const char* message) {
  try {
    return record(engine, code, std::string(message));
  } catch (...) {
    return record(engine, code, std::string());
  }
}

// A query that succeeded: this thread has no error on `engine` any more (clear() keeps the
// string's storage: no allocation).
void record_success(const exao_engine* engine) noexcept {
  t_last.engine = engine;
  t_last.message.clear();
}

// The C boundary: no C++ exception may reach a C caller. The C++ API throws none; this catches
// what the conversions here might (std::bad_alloc from a message string).
template <class Body>
exao_status c_boundary(const exao_engine* engine, Body&& body) noexcept {
  try {
    const exao_status status = body();
    if (status == EXAO_OK && engine) record_success(engine);
    return status;
  } catch (const std::bad_alloc&) {
    return engine ? record(engine, StatusCode::OutOfMemory, "out of memory") : EXAO_OUT_OF_MEMORY;
  } catch (...) {
    return engine ? record(engine, StatusCode::InternalError, "unexpected exception") : EXAO_INTERNAL_ERROR;
  }
}

exao::api::Options to_cpp(const exao_options* o) {
  exao::api::Options out;
  if (!o) return out;
  // A negative radius is the C spelling of C++'s nullopt (the default); 0 and NaN stay, and are
  // refused as C++ refuses them.
  if (!(o->radius < 0.0f)) out.radius = o->radius;
  out.samples = o->samples;
  out.falloff = static_cast<exao::api::Falloff>(o->falloff);
  out.pattern_seed = o->pattern_seed;
  out.sidedness = static_cast<exao::api::Sidedness>(o->sidedness);
  out.mask_mode = static_cast<exao::api::MaskMode>(o->mask_mode);
  if (!(o->origin_offset < 0.0f)) out.origin_offset = o->origin_offset;  // NaN stays, and is refused
  out.threads = o->threads;
  out.backend = static_cast<exao::api::Backend>(o->backend);
  out.table_resolution = o->table_resolution;
  out.bvh_branching = o->bvh_branching;
  out.embree_rays = static_cast<exao::api::EmbreeRays>(o->embree_rays);
  return out;
}

exao::api::Mesh to_cpp(const exao_mesh& m) {
  exao::api::Mesh out;
  out.vertices = m.vertices;
  out.vertex_count = m.vertex_count;
  out.vertex_stride = m.vertex_stride == 0 ? 3 * sizeof(float) : m.vertex_stride;
  out.indices = m.indices;
  out.index_stride = m.index_stride == 0 ? 3 * sizeof(std::uint32_t) : m.index_stride;
  out.triangle_count = m.triangle_count;
  out.two_sided = m.two_sided;
  out.transform = m.transform;
  return out;
}

exao::api::Receiver to_cpp(const exao_receiver& r) {
  return {{r.position[0], r.position[1], r.position[2]}, {r.normal[0], r.normal[1], r.normal[2]}, r.key,
          r.exclude == 0 ? exao::api::kNoObject : r.exclude - 1};
}

// Wraps a built engine in a handle, or reports the build's error.
exao_status finish_create(exao::api::Result<Engine>&& built, exao_engine** engine, char* error_buffer,
                          std::size_t error_buffer_size) {
  if (!built) {
    copy_message(built.error().message, error_buffer, error_buffer_size);
    return to_c(built.error().code);
  }
  exao_engine* handle = new (std::nothrow) exao_engine(std::move(*built));
  if (!handle) {
    copy_message("out of memory", error_buffer, error_buffer_size);
    return EXAO_OUT_OF_MEMORY;
  }
  *engine = handle;
  copy_message("", error_buffer, error_buffer_size);
  return EXAO_OK;
}

// Batch receivers converted to the C++ type (the same layout, but distinct types).
std::optional<std::vector<exao::api::Receiver>> convert(const exao_receiver* receivers, std::size_t count) {
  try {
    std::vector<exao::api::Receiver> out(count);
    for (std::size_t i = 0; i < count; ++i) out[i] = to_cpp(receivers[i]);
    return out;
  } catch (...) {
    return std::nullopt;
  }
}

}  // namespace

extern "C" {

const char* exao_status_string(exao_status status) {
  const int s = static_cast<int>(status);
  if (s < EXAO_OK || s > EXAO_CALLBACK_ERROR) return "unknown status";
  return exao::api::status_text(static_cast<StatusCode>(s));
}

const char* exao_version(void) { return exao::api::version(); }

void exao_options_init(exao_options* options) {
  if (!options) return;
  const exao::api::Options d;
  options->radius = -1.0f;
  options->samples = d.samples;
  options->falloff = static_cast<exao_falloff>(d.falloff);
  options->pattern_seed = d.pattern_seed;
  options->sidedness = static_cast<exao_sidedness>(d.sidedness);
  options->mask_mode = static_cast<exao_mask_mode>(d.mask_mode);
  options->origin_offset = -1.0f;
  options->threads = d.threads;
  options->backend = static_cast<exao_backend>(d.backend);
  options->table_resolution = d.table_resolution;
  options->bvh_branching = d.bvh_branching;
  options->embree_rays = static_cast<exao_embree_rays>(d.embree_rays);
}

exao_status exao_engine_create(const exao_mesh* meshes, size_t mesh_count, const exao_options* options,
                               exao_engine** engine, char* error_buffer, size_t error_buffer_size) {
  if (!engine) {
    copy_message("engine: null", error_buffer, error_buffer_size);
    return EXAO_INVALID_ARGUMENT;
  }
  *engine = nullptr;
  if (!meshes || mesh_count == 0) {
    copy_message(!meshes ? "meshes: null" : "mesh_count: 0", error_buffer, error_buffer_size);
    return EXAO_INVALID_ARGUMENT;
  }
  std::vector<exao::api::Mesh> converted;
  try {
    converted.resize(mesh_count);
  } catch (...) {
    copy_message("out of memory", error_buffer, error_buffer_size);
    return EXAO_OUT_OF_MEMORY;
  }
  for (std::size_t k = 0; k < mesh_count; ++k) converted[k] = to_cpp(meshes[k]);
  return finish_create(Engine::build(converted, to_cpp(options)), engine, error_buffer, error_buffer_size);
}

exao_status exao_engine_open(const char* name_or_path, const exao_options* options, exao_engine** engine,
                             char* error_buffer, size_t error_buffer_size) {
  if (!engine) {
    copy_message("engine: null", error_buffer, error_buffer_size);
    return EXAO_INVALID_ARGUMENT;
  }
  *engine = nullptr;
  if (!name_or_path) {
    copy_message("name_or_path: null", error_buffer, error_buffer_size);
    return EXAO_INVALID_ARGUMENT;
  }
  return finish_create(Engine::open(name_or_path, to_cpp(options)), engine, error_buffer, error_buffer_size);
}

exao_status exao_engine_with_settings(const exao_engine* engine, float radius, float origin_offset, int samples,
                                      exao_engine** derived, char* error_buffer, size_t error_buffer_size) {
  if (!derived) {
    copy_message("derived: null", error_buffer, error_buffer_size);
    return EXAO_INVALID_ARGUMENT;
  }
  *derived = nullptr;
  if (!engine) {
    copy_message("engine: null", error_buffer, error_buffer_size);
    return EXAO_INVALID_ARGUMENT;
  }
  try {
    exao::api::QuerySettings settings;
    // Negative (and 0 samples) are C's spelling of "the engine's own", as in exao_options.
    if (!(radius < 0.0f)) settings.radius = radius;
    if (!(origin_offset < 0.0f)) settings.origin_offset = origin_offset;
    if (samples != 0) settings.samples = samples;
    return finish_create(engine->engine.with_settings(settings), derived, error_buffer, error_buffer_size);
  } catch (...) {
    copy_message("out of memory", error_buffer, error_buffer_size);
    return EXAO_OUT_OF_MEMORY;
  }
}

void exao_engine_destroy(exao_engine* engine) {
  // A later engine at the same address must not inherit this thread's message.
  if (engine && t_last.engine == engine) record_success(nullptr);
  delete engine;
}

exao_status exao_engine_get_info(const exao_engine* engine, exao_engine_info* info) {
  if (!engine || !info) return EXAO_INVALID_ARGUMENT;
  const exao::api::EngineInfo& i = engine->engine.info();
  info->backend = static_cast<exao_backend>(i.backend);
  info->mask_mode = static_cast<exao_mask_mode>(i.mask_mode);
  info->falloff = static_cast<exao_falloff>(i.falloff);
  info->samples = i.samples;
  info->mask_words = i.mask_words;
  info->radius = i.radius;
  info->origin_offset = i.origin_offset;
  info->threads = i.threads;
  info->triangles = i.triangles;
  info->two_sided_triangles = i.two_sided_triangles;
  info->zero_area_skipped = i.zero_area_skipped;
  info->beyond_limit_skipped = i.beyond_limit_skipped;
  info->bounds_lo[0] = i.bounds_lo.x;
  info->bounds_lo[1] = i.bounds_lo.y;
  info->bounds_lo[2] = i.bounds_lo.z;
  info->bounds_hi[0] = i.bounds_hi.x;
  info->bounds_hi[1] = i.bounds_hi.y;
  info->bounds_hi[2] = i.bounds_hi.z;
  info->table_resolution = i.table_resolution;
  info->table_bytes = i.table_bytes;
  info->simd = i.simd;
  info->origin_offset_per_magnitude = i.origin_offset_per_magnitude;
  return EXAO_OK;
}

int exao_engine_samples(const exao_engine* engine) { return engine ? engine->engine.samples() : 0; }

size_t exao_engine_last_error(const exao_engine* engine, char* buffer, size_t buffer_size) {
  if (!engine) {
    copy_message("", buffer, buffer_size);
    return 0;
  }
  static const std::string kNone;
  return copy_message(t_last.engine == engine ? t_last.message : kNone, buffer, buffer_size);
}

exao_status exao_ao(const exao_engine* engine, const float position[3], const float normal[3], uint64_t key, float* ao) {
  return c_boundary(engine, [&]() -> exao_status {
    if (!engine) return EXAO_INVALID_ARGUMENT;
    if (!position || !normal || !ao) return record(engine, StatusCode::InvalidArgument, "position, normal or ao: null");
    const exao::api::Result<float> result =
        engine->engine.ao({position[0], position[1], position[2]}, {normal[0], normal[1], normal[2]}, key);
    if (!result) return record(engine, result.error());
    *ao = *result;
    return EXAO_OK;
  });
}

exao_status exao_mask(const exao_engine* engine, const float position[3], const float normal[3], uint64_t key,
                      uint64_t* words, size_t word_count, float* origin, float* directions, float* lengths) {
  return c_boundary(engine, [&]() -> exao_status {
    if (!engine) return EXAO_INVALID_ARGUMENT;
    if (!position || !normal || !words) return record(engine, StatusCode::InvalidArgument, "position, normal or words: null");
    const std::size_t need = engine->engine.mask_words();
    if (word_count < need) {
      return record(engine, Error{StatusCode::InvalidArgument,
                                  "word_count: " + std::to_string(word_count) + " is less than (N + 63) / 64 = " + std::to_string(need)});
    }
    const exao::api::Receiver receiver{{position[0], position[1], position[2]}, {normal[0], normal[1], normal[2]}, key};
    const auto n = static_cast<std::size_t>(engine->engine.samples());
    std::array<exao::api::ShadowRay, exao::api::RayMask::kMaxSamples> rays;  // 16 KiB on the stack, no allocation
    const bool want_rays = directions || lengths || origin;
    const exao::api::Result<exao::api::RayMask> mask =
        engine->engine.mask(receiver, want_rays ? std::span<exao::api::ShadowRay>(rays.data(), n) : std::span<exao::api::ShadowRay>());
    if (!mask) return record(engine, mask.error());
    exao::api::Vec3 o;
    if (origin) {
      const exao::api::Status ok = engine->engine.rays(receiver, o, std::span<exao::api::ShadowRay>(rays.data(), n));
      if (!ok) return record(engine, ok.error());
      origin[0] = o.x;
      origin[1] = o.y;
      origin[2] = o.z;
    }
    for (std::size_t w = 0; w < word_count; ++w) words[w] = w < need ? mask->words[w] : 0;
    for (std::size_t i = 0; want_rays && i < n; ++i) {
      if (directions) {
        directions[3 * i + 0] = rays[i].direction.x;
        directions[3 * i + 1] = rays[i].direction.y;
        directions[3 * i + 2] = rays[i].direction.z;
      }
      if (lengths) lengths[i] = rays[i].length;
    }
    return EXAO_OK;
  });
}

exao_status exao_ao_batch(const exao_engine* engine, const exao_receiver* receivers, size_t count, float* ao) {
  return c_boundary(engine, [&]() -> exao_status {
    if (!engine) return EXAO_INVALID_ARGUMENT;
    if (count == 0) return EXAO_OK;
    if (!receivers || !ao) return record(engine, StatusCode::InvalidArgument, "receivers or ao: null");
    std::optional<std::vector<exao::api::Receiver>> converted = convert(receivers, count);
    if (!converted) return record(engine, StatusCode::OutOfMemory, "out of memory");
    const exao::api::Status ok = engine->engine.ao(*converted, std::span<float>(ao, count));
    return ok ? EXAO_OK : record(engine, ok.error());
  });
}

exao_status exao_ao_batch_statuses(const exao_engine* engine, const exao_receiver* receivers, size_t count, float* ao,
                                   exao_status* statuses) {
  return c_boundary(engine, [&]() -> exao_status {
    if (!engine) return EXAO_INVALID_ARGUMENT;
    if (count == 0) return EXAO_OK;
    if (!receivers || !ao || !statuses) return record(engine, StatusCode::InvalidArgument, "receivers, ao or statuses: null");
    std::optional<std::vector<exao::api::Receiver>> converted = convert(receivers, count);
    if (!converted) return record(engine, StatusCode::OutOfMemory, "out of memory");
    std::vector<StatusCode> codes(count, StatusCode::Ok);
    exao::api::BatchOptions batch;
    batch.statuses = codes;
    const exao::api::Status ok = engine->engine.ao(*converted, std::span<float>(ao, count), batch);
    for (std::size_t i = 0; i < count; ++i) statuses[i] = to_c(codes[i]);
    return ok ? EXAO_OK : record(engine, ok.error());
  });
}

exao_status exao_mask_batch(const exao_engine* engine, const exao_receiver* receivers, size_t count, uint64_t* words) {
  return c_boundary(engine, [&]() -> exao_status {
    if (!engine) return EXAO_INVALID_ARGUMENT;
    if (count == 0) return EXAO_OK;
    if (!receivers || !words) return record(engine, StatusCode::InvalidArgument, "receivers or words: null");
    std::optional<std::vector<exao::api::Receiver>> converted = convert(receivers, count);
    if (!converted) return record(engine, StatusCode::OutOfMemory, "out of memory");
    const exao::api::Status ok =
        engine->engine.masks(*converted, std::span<std::uint64_t>(words, count * engine->engine.mask_words()));
    return ok ? EXAO_OK : record(engine, ok.error());
  });
}

}  // extern "C"
