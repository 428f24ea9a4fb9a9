#include "core/embree_reference.h"

#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <mutex>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/cutouts.h"
#include "core/surface_rule.h"

namespace exao {

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  // The vertices Embree reads, 3 per scene triangle in the scene's order (9 floats each), in
  // one buffer both geometries share: the caller's (build_sharing) or this copy (padded).
  std::vector<glm::vec3> own_vertices;
  const float* vertices = nullptr;
  std::size_t vertex_count = 0;
  bool shared = false;
  // Per Embree geometry, three indices per primitive: 3t, 3t + 1, 3t + 2 for scene triangle t,
  // so the index buffer is also the way back to the scene (t = indices[3 prim] / 3).
  std::vector<unsigned> indices[2];
  // What each geometry's occlusion filter reads (its user data). The one-sided geometry's
  // front-face normals are computed from the vertices at each hit, by the expression build
  // used to store them (the same floats: 12 bytes a triangle fewer, and only hits pay).
  struct FilterData {
    const float* vertices = nullptr;          // the shared vertex buffer: 9 floats per scene triangle
    const unsigned* indices = nullptr;        // the geometry's index buffer
    bool one_sided = false;
    const Cutouts* cutouts = nullptr;          // null: every triangle opaque
    const std::uint32_t* objects = nullptr;    // per scene triangle: Scene::object; null: all 0
  };
  std::shared_ptr<const Cutouts> cutouts;
  std::vector<std::uint32_t> objects;  // Scene::object, or empty when the scene has none
  FilterData filter_data[2];
  std::mutex error_mutex;
  std::string first_error;

  [[nodiscard]] std::uint32_t scene_triangle(unsigned geometry, unsigned prim) const {
    return indices[geometry][3 * static_cast<std::size_t>(prim)] / 3;
  }

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

constexpr unsigned kOneSided = 0;
constexpr unsigned kTwoSided = 1;
constexpr std::size_t kVertexPadding = Scene::kVertexPadding;

void on_embree_error(void* user, RTCError code, const char* message) {
  auto* impl = static_cast<EmbreeScene::Impl*>(user);
  std::lock_guard lock(impl->error_mutex);
  if (impl->first_error.empty()) {
    impl->first_error = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
  }
}

// The occlusion filter of both geometries: DESIGN.md section 1's sidedness and the surface rule.
// - A one-sided triangle blocks a ray only when the ray arrives at its front face, i.e. travels
//   against the counter-clockwise normal.
// - A triangle of the object the ray's receiver excludes (Receiver::excluded_object, carried in
//   the ray's id) blocks nothing: the masks skip the same triangles.
// - A triangle whose plane the ray origin lies on blocks nothing (core/surface_rule.h).
//   Embree's own test (t > tnear = 0) gives that only where rounding leaves t = 0 exactly (an
//   axis-aligned plane); on a tilted plane it hits about half such rays, so the shared test
//   decides. Only hits reach the filter: a few tens of flops per blocked ray.
void occlusion_filter(const RTCFilterFunctionNArguments* args) {
  const auto* data = static_cast<const EmbreeScene::Impl::FilterData*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    const std::uint32_t t = data->indices[3 * static_cast<std::size_t>(prim)] / 3;
    const std::uint32_t object = data->objects ? data->objects[t] : 0;
    if (object == RTCRayN_id(args->ray, args->N, i)) {
      args->valid[i] = 0;
      continue;
    }
    const float* v = data->vertices + 9 * static_cast<std::size_t>(t);
    const glm::vec3 a{v[0], v[1], v[2]}, b{v[3], v[4], v[5]}, c{v[6], v[7], v[8]};
    if (data->one_sided) {
      const glm::vec3 n = glm::cross(b - a, c - a);
      const float along = RTCRayN_dir_x(args->ray, args->N, i) * n.x + RTCRayN_dir_y(args->ray, args->N, i) * n.y +
                          RTCRayN_dir_z(args->ray, args->N, i) * n.z;
      if (!(along < 0.0f)) {
        args->valid[i] = 0;
        continue;
      }
    }
    const glm::vec3 origin{RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                           RTCRayN_org_z(args->ray, args->N, i)};
    if (origin_on_plane(a, b, c, origin)) {
      args->valid[i] = 0;
      continue;
    }
    // A cut-out decides by its alpha at the hit, from the ray's floats (core/cutouts.h), as the masks do.
    if (data->cutouts) {
      const glm::vec3 direction{RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                                RTCRayN_dir_z(args->ray, args->N, i)};
      if (!data->cutouts->blocks(t, origin, direction)) args->valid[i] = 0;
    }
  }
}

// The closest-hit filter of a scene with cut-outs: a camera ray passes through a cut-out hole.
void cutout_intersect_filter(const RTCFilterFunctionNArguments* args) {
  const auto* data = static_cast<const EmbreeScene::Impl::FilterData*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    const std::uint32_t t = data->indices[3 * static_cast<std::size_t>(prim)] / 3;
    const glm::vec3 origin{RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                           RTCRayN_org_z(args->ray, args->N, i)};
    const glm::vec3 direction{RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                              RTCRayN_dir_z(args->ray, args->N, i)};
    if (!data->cutouts->blocks(t, origin, direction)) args->valid[i] = 0;
  }
}

// One geometry over the shared vertex buffer: its own index buffer (shared too, this scene's),
// the filters and their data.
void attach_triangles(EmbreeScene::Impl& impl, unsigned id) {
  const std::vector<unsigned>& indices = impl.indices[id];
  if (indices.empty()) return;
  RTCGeometry geometry = rtcNewGeometry(impl.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, impl.vertices, 0,
                             3 * sizeof(float), impl.vertex_count);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices.data(), 0,
                             3 * sizeof(unsigned), indices.size() / 3);
  EmbreeScene::Impl::FilterData& data = impl.filter_data[id];
  data.vertices = impl.vertices;
  data.indices = indices.data();
  data.one_sided = id == kOneSided;
  data.objects = impl.objects.empty() ? nullptr : impl.objects.data();
  data.cutouts = impl.cutouts.get();
  rtcSetGeometryUserData(geometry, &data);
  rtcSetGeometryOccludedFilterFunction(geometry, occlusion_filter);
  if (impl.cutouts) rtcSetGeometryIntersectFilterFunction(geometry, cutout_intersect_filter);
  rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
  rtcCommitGeometry(geometry);
  rtcAttachGeometryByID(impl.scene, geometry, id);
  rtcReleaseGeometry(geometry);
}

// Denormals make traversal slow for no benefit in a ray caster: flush them, per worker thread.
void flush_denormals() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

template <int K>
struct Packet;
template <>
struct Packet<4> {
  using Ray = RTCRay4;
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) { rtcOccluded4(valid, s, c, r); }
};
template <>
struct Packet<8> {
  using Ray = RTCRay8;
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) { rtcOccluded8(valid, s, c, r); }
};
template <>
struct Packet<16> {
  using Ray = RTCRay16;
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) { rtcOccluded16(valid, s, c, r); }
};

template <class Ray>
void set_lane(Ray& ray, int lane, const Frame& frame, const ShadowRays& rays, int sample) {
  const glm::vec3 d = rays.world_direction(frame, sample);
  ray.org_x[lane] = frame.origin.x;
  ray.org_y[lane] = frame.origin.y;
  ray.org_z[lane] = frame.origin.z;
  ray.dir_x[lane] = d.x;
  ray.dir_y[lane] = d.y;
  ray.dir_z[lane] = d.z;
  ray.tnear[lane] = 0.0f;
  ray.tfar[lane] = rays.pattern.lengths[sample] * rays.radius;
  ray.time[lane] = 0.0f;
  ray.mask[lane] = 0xFFFFFFFFu;
  ray.id[lane] = frame.excluded_object;  // read by the occlusion filter
  ray.flags[lane] = 0;
}

// Rays of receivers [begin, end), K at a time.
template <int K>
void cast_packets(RTCScene scene, const ShadowRays& rays, std::span<const Receiver> receivers, std::size_t begin,
                  std::size_t end, const EmbreeOptions& options, MaskSet& masks) {
  using P = Packet<K>;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  if (options.coherent) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) int valid[K];
  alignas(64) typename P::Ray packet;
  const int n = rays.count();

  if (options.across_receivers) {
    Frame frames[K];
    for (std::size_t first = begin; first < end; first += K) {
      const int lanes = static_cast<int>(std::min<std::size_t>(K, end - first));
      for (int lane = 0; lane < lanes; ++lane) frames[lane] = rays.frame(receivers[first + lane]);
      for (int sample = 0; sample < n; ++sample) {
        for (int lane = 0; lane < K; ++lane) {
          valid[lane] = lane < lanes ? -1 : 0;
          set_lane(packet, lane, frames[lane < lanes ? lane : 0], rays, sample);
        }
        P::occluded(valid, scene, &context, &packet);
        for (int lane = 0; lane < lanes; ++lane) {
          if (packet.tfar[lane] == -std::numeric_limits<float>::infinity()) {
            masks.row(first + lane)[sample / 64] |= std::uint64_t{1} << (sample % 64);
          }
        }
      }
    }
  } else {
    for (std::size_t r = begin; r < end; ++r) {
      const Frame frame = rays.frame(receivers[r]);
      std::span<std::uint64_t> row = masks.row(r);
      for (int first = 0; first < n; first += K) {
        for (int lane = 0; lane < K; ++lane) {
          valid[lane] = -1;  // N is a multiple of 32, so packets are always full
          set_lane(packet, lane, frame, rays, first + lane);
        }
        P::occluded(valid, scene, &context, &packet);
        for (int lane = 0; lane < K; ++lane) {
          if (packet.tfar[lane] == -std::numeric_limits<float>::infinity()) {
            row[(first + lane) / 64] |= std::uint64_t{1} << ((first + lane) % 64);
          }
        }
      }
    }
  }
}

void cast_single(RTCScene scene, const ShadowRays& rays, std::span<const Receiver> receivers, std::size_t begin,
                 std::size_t end, MaskSet& masks) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  const int n = rays.count();
  for (std::size_t r = begin; r < end; ++r) {
    const Frame frame = rays.frame(receivers[r]);
    std::span<std::uint64_t> row = masks.row(r);
    for (int sample = 0; sample < n; ++sample) {
      const glm::vec3 d = rays.world_direction(frame, sample);
      RTCRay ray{frame.origin.x, frame.origin.y, frame.origin.z, 0.0f, d.x, d.y, d.z, 0.0f,
                 rays.pattern.lengths[sample] * rays.radius, 0xFFFFFFFFu, frame.excluded_object, 0};
      rtcOccluded1(scene, &context, &ray);
      if (ray.tfar == -std::numeric_limits<float>::infinity()) row[sample / 64] |= std::uint64_t{1} << (sample % 64);
    }
  }
}

}  // namespace

std::size_t EmbreeScene::occlude_selected(const ShadowRays& rays, std::span<const Frame> frames,
                                          std::span<const std::uint64_t> wanted, std::size_t words,
                                          std::span<std::uint64_t> blocked) const {
  constexpr int K = 16;
  flush_denormals();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) int valid[K];
  alignas(64) RTCRay16 packet;
  const int n = rays.count();
  std::size_t cast = 0;
  for (std::size_t first = 0; first < frames.size(); first += K) {
    const int lanes = static_cast<int>(std::min<std::size_t>(K, frames.size() - first));
    // The samples any lane wants: the OR of the group's rows, walked by bit scans.
    std::uint64_t any[16] = {};
    const std::size_t row_words = std::min<std::size_t>(words, 16);
    for (int lane = 0; lane < lanes; ++lane) {
      for (std::size_t w = 0; w < row_words; ++w) any[w] |= wanted[(first + lane) * words + w];
    }
    for (std::size_t w = 0; w < row_words; ++w) {
      for (std::uint64_t bits = any[w]; bits; bits &= bits - 1) {
        const int sample = static_cast<int>(64 * w) + std::countr_zero(bits);
        if (sample >= n) break;
        int live = 0;
        // Every lane holds a real ray, the ones not wanted too (their answers are not read): on
        // an AVX2 machine Debian's Embree 3 asserted on the stale rays of inactive lanes
        // (ray.valid(), in its 8-wide hybrid occluded) and aborted the program.
        for (int lane = 0; lane < K; ++lane) {
          const bool on = lane < lanes && ((wanted[(first + lane) * words + w] >> (sample % 64)) & 1u);
          valid[lane] = on ? -1 : 0;
          set_lane(packet, lane, frames[first + (lane < lanes ? lane : 0)], rays, sample);
          live += on;
        }
        cast += static_cast<std::size_t>(live);
        rtcOccluded16(valid, impl_->scene, &context, &packet);
        for (int lane = 0; lane < lanes; ++lane) {
          if (valid[lane] && packet.tfar[lane] == -std::numeric_limits<float>::infinity()) {
            blocked[(first + lane) * words + w] |= std::uint64_t{1} << (sample % 64);
          }
        }
      }
    }
  }
  return cast;
}

const char* embree_rays_name(EmbreeRays rays) { return name_of(rays); }

Result<EmbreeRays> parse_embree_rays(const std::string& name) {
  if (const std::optional<EmbreeRays> r = parse_enum<EmbreeRays>(name)) return *r;
  return fail("embree.rays: unknown mode '" + name + "' (" + name_list<EmbreeRays>() + ")");
}

EmbreeScene::EmbreeScene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;
EmbreeScene::~EmbreeScene() = default;

Result<EmbreeScene> EmbreeScene::build(const Scene& scene, const ProgressCallback& progress) {
  return build(scene, false, progress);
}

Result<EmbreeScene> EmbreeScene::build_sharing(const Scene& scene, const ProgressCallback& progress) {
  return build(scene, true, progress);
}

namespace {
// Embree's build progress (a fraction, from its worker threads) as thousandths.
bool report_build_progress(void* callback, double fraction) {
  const auto& progress = *static_cast<const ProgressCallback*>(callback);
  progress(static_cast<std::size_t>(std::clamp(fraction, 0.0, 1.0) * 1000.0), 1000);
  return true;
}
}  // namespace

Result<EmbreeScene> EmbreeScene::build(const Scene& scene, bool share, const ProgressCallback& progress) {
  const std::size_t n = scene.triangle_count();
  if (3 * n > std::numeric_limits<unsigned>::max()) {
    return fail("Embree: " + std::to_string(n) + " triangles is more than 32-bit vertex indices address");
  }
  auto impl = std::make_unique<Impl>();
  impl->device = rtcNewDevice(nullptr);
  if (!impl->device) return fail("Embree: cannot create a device (" + std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(impl->device, on_embree_error, impl.get());
  impl->scene = rtcNewScene(impl->device);
  rtcSetSceneBuildQuality(impl->scene, RTC_BUILD_QUALITY_HIGH);
  if (scene.cutouts && scene.cutouts->any()) impl->cutouts = scene.cutouts;

  // Embree reads a vertex with a 16-byte load, so the last one needs readable bytes after it:
  // the caller's spare capacity, or this copy's padding.
  impl->shared = share && scene.vertices.capacity() >= scene.vertices.size() + kVertexPadding;
  if (impl->shared) {
    impl->vertices = &scene.vertices.data()->x;
  } else {
    impl->own_vertices.reserve(scene.vertices.size() + kVertexPadding);
    impl->own_vertices.assign(scene.vertices.begin(), scene.vertices.end());
    impl->vertices = &impl->own_vertices.data()->x;
  }
  impl->vertex_count = scene.vertices.size();
  const std::size_t two_sided = two_sided_count(scene);
  impl->indices[kOneSided].reserve(3 * (n - two_sided));
  impl->indices[kTwoSided].reserve(3 * two_sided);
  for (std::uint32_t t = 0; t < n; ++t) {
    std::vector<unsigned>& indices = impl->indices[scene.two_sided[t] ? kTwoSided : kOneSided];
    indices.insert(indices.end(), {3 * t, 3 * t + 1, 3 * t + 2});
  }
  if (std::any_of(scene.object.begin(), scene.object.end(), [](std::uint32_t o) { return o != 0; })) {
    impl->objects.assign(scene.object.begin(), scene.object.end());
    impl->objects.resize(n, 0);
  }
  attach_triangles(*impl, kOneSided);
  attach_triangles(*impl, kTwoSided);
  if (progress) rtcSetSceneProgressMonitorFunction(impl->scene, report_build_progress, const_cast<ProgressCallback*>(&progress));
  rtcCommitScene(impl->scene);
  rtcSetSceneProgressMonitorFunction(impl->scene, nullptr, nullptr);
  if (!impl->first_error.empty()) return fail(impl->first_error);
  return EmbreeScene(std::move(impl));
}

bool EmbreeScene::shares_vertices() const { return impl_->shared; }

Result<void> EmbreeScene::refit(std::span<const glm::vec3> vertices) {
  Impl& impl = *impl_;
  if (vertices.size() != impl.vertex_count) {
    return fail("refit: " + std::to_string(vertices.size()) + " vertices for " + std::to_string(impl.vertex_count / 3) +
                " triangles (3 each)");
  }
  // A shared buffer is the caller's, moved already (build_sharing's contract); a copy is ours.
  if (impl.shared && &vertices.data()->x != impl.vertices) {
    return fail("refit: this Embree scene reads the caller's vertices in place (build_sharing): move those");
  }
  if (!impl.shared) std::copy(vertices.begin(), vertices.end(), impl.own_vertices.begin());
  for (const unsigned id : {kOneSided, kTwoSided}) {
    if (impl.indices[id].empty()) continue;
    RTCGeometry geometry = rtcGetGeometry(impl.scene, id);
    rtcUpdateGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_REFIT);
    rtcCommitGeometry(geometry);
  }
  rtcCommitScene(impl.scene);
  const std::lock_guard lock(impl.error_mutex);
  if (!impl.first_error.empty()) return fail(impl.first_error);
  return {};
}

std::optional<EmbreeScene::Hit> EmbreeScene::closest_hit(const glm::vec3& origin, const glm::vec3& direction) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit query{};
  query.ray = RTCRay{origin.x, origin.y, origin.z, 0.0f, direction.x, direction.y, direction.z, 0.0f,
                     std::numeric_limits<float>::infinity(), 0xFFFFFFFFu, kNoObject, 0};
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &query);
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  return Hit{impl_->scene_triangle(query.hit.geomID, query.hit.primID), query.ray.tfar};
}

MaskSet EmbreeScene::occlusion(const ShadowRays& rays, std::span<const Receiver> receivers,
                               const EmbreeOptions& options, const ProgressCallback& progress) const {
  MaskSet masks(receivers.size(), rays.count());
  ProgressCounter counter(progress, receivers.size());
  // Chunks of 64 receivers: a multiple of every packet width, and plenty of tasks to balance.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, receivers.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      flush_denormals();
                      switch (options.rays) {
                        case EmbreeRays::Single:
                          cast_single(impl_->scene, rays, receivers, range.begin(), range.end(), masks);
                          break;
                        case EmbreeRays::Packet4:
                          cast_packets<4>(impl_->scene, rays, receivers, range.begin(), range.end(), options, masks);
                          break;
                        case EmbreeRays::Packet8:
                          cast_packets<8>(impl_->scene, rays, receivers, range.begin(), range.end(), options, masks);
                          break;
                        case EmbreeRays::Packet16:
                          cast_packets<16>(impl_->scene, rays, receivers, range.begin(), range.end(), options, masks);
                          break;
                      }
                      counter.add(range.size());
                    });
  return masks;
}

}  // namespace exao
