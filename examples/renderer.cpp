// exao_renderer: a small offline renderer that uses exao as a drop-in for its AO ray loop.
//
// Embree traces the camera rays, the mirror reflections, one diffuse bounce and the shadow rays
// of a point light; exao gives the ambient occlusion at every diffuse shading point, wherever it
// is: seen directly, in a mirror, or through the bounce. A screen-space or rasterised AO knows
// only the points the camera sees directly, so it cannot shade the other two kinds.
//
// The scene is exao's built-in room with two mirrors added by this program: a mirror on the
// right wall and a mirror ball on the floor, and a row of pebbles: one small mesh placed many
// times, as Embree instances in the renderer's tracer and as exao::api::Instance in exao (no
// copy by the renderer). Uses only the public API (exao/exao.hpp), Embree and libpng.
//
//     exao_renderer [-o renderer.png] [-W 960] [-H 540] [--spp 4] [--samples 64] [--radius 1]
//                   [--object-radius 0.4] [--measure-ao]
//
// --radius is the AO distance of the room's floor, walls and ceiling, --object-radius that of
// the objects in it (a per-material AO distance: one engine, and one derived from it with
// Engine::with_settings, a per-call setting over the same scene).
//
// --measure-ao renders no image: it collects the diffuse shading points of the camera's paths
// (one per pixel, mirrors followed) and times their AO pass three ways at --samples rays:
// exao's batch query, exao's single queries from the renderer's threads, and the renderer's
// own loop of rtcOccluded16 (16 cosine-weighted rays of a point per packet, the per-material
// distance as tfar). scripts/renderer-ao.sh runs it at N = 64 and 256.

#include <embree3/rtcore.h>
#include <png.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <exao/exao.hpp>

namespace {

using exao::api::Vec3;

Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3 operator*(float s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
Vec3 normalize(Vec3 a) { return (1.0f / std::sqrt(dot(a, a))) * a; }

// --- The scene: exao's room plus the example's own mirrors ----------------------------------

struct Geometry {
  std::vector<float> positions;       // 9 floats per triangle: the room, then the mirrors
  std::vector<std::uint8_t> two_sided;
  std::size_t first_mirror = 0;       // triangles from here on are mirrors
  std::size_t first_ball = 0;         // ... and from here on the mirror ball's
  Vec3 ball_centre;
  exao::api::Camera camera;
  // The pebble: one mesh (a soup, model units, faces outward) and where it is placed: row-major
  // 3x4 matrices, uniform scale and translation (so a model normal is a world normal).
  std::vector<float> pebble;
  std::vector<std::array<float, 12>> pebble_at;
};

void add_triangle(Geometry& g, Vec3 a, Vec3 b, Vec3 c) {
  g.positions.insert(g.positions.end(), {a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z});
  g.two_sided.push_back(0);  // one-sided, front faces counter-clockwise: they face the room
}

// A UV sphere, faces outward, into a soup of 9 floats per triangle.
void add_sphere(std::vector<float>& out, Vec3 centre, Vec3 radii, int slices, int stacks) {
  const auto point = [&](int i, int j) {
    const float phi = 6.2831853f * static_cast<float>(i) / static_cast<float>(slices);
    const float theta = 3.1415927f * static_cast<float>(j) / static_cast<float>(stacks);
    return centre + radii * Vec3{std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi)};
  };
  const auto put = [&](Vec3 a, Vec3 b, Vec3 c) { out.insert(out.end(), {a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z}); };
  for (int j = 0; j < stacks; ++j) {
    for (int i = 0; i < slices; ++i) {
      const Vec3 a = point(i, j), b = point(i, j + 1), c = point(i + 1, j + 1), d = point(i + 1, j);
      if (j > 0) put(a, b, d);
      if (j < stacks - 1) put(d, b, c);
    }
  }
}

// A UV sphere, faces outward.
void add_sphere(Geometry& g, Vec3 centre, float radius, int slices, int stacks) {
  const auto point = [&](int i, int j) {
    const float phi = 6.2831853f * static_cast<float>(i) / static_cast<float>(slices);
    const float theta = 3.1415927f * static_cast<float>(j) / static_cast<float>(stacks);
    return centre + radius * Vec3{std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi)};
  };
  for (int j = 0; j < stacks; ++j) {
    for (int i = 0; i < slices; ++i) {
      const Vec3 a = point(i, j), b = point(i, j + 1), c = point(i + 1, j + 1), d = point(i + 1, j);
      if (j > 0) add_triangle(g, a, b, d);
      if (j < stacks - 1) add_triangle(g, d, b, c);
    }
  }
}

Geometry make_scene() {
  exao::api::Result<exao::api::SceneData> room = exao::api::load_scene("room");
  if (!room) {
    std::fprintf(stderr, "exao_renderer: %s\n", room.error().message.c_str());
    std::exit(1);
  }
  Geometry g;
  g.positions = room->positions;
  g.two_sided = room->two_sided;
  g.camera = room->cameras.front();
  g.first_mirror = g.two_sided.size();
  // A 5 x 3 mirror on the right wall (x = 5), 2 mm in front of it, facing -X.
  const float x = 4.998f;
  const Vec3 a{x, 0.5f, 2.6f}, b{x, 0.5f, -2.4f}, c{x, 3.5f, -2.4f}, d{x, 3.5f, 2.6f};
  add_triangle(g, a, b, c);
  add_triangle(g, a, c, d);
  // A mirror ball on the floor, near the camera: it shows the room behind the camera.
  g.first_ball = g.two_sided.size();
  g.ball_centre = {-1.2f, 0.7f, 1.3f};
  add_sphere(g, g.ball_centre, 0.7f, 64, 32);
  // Pebbles: a flattened sphere resting on its base (model y in [0, 0.5]), placed along the
  // front of the floor, bigger and smaller.
  add_sphere(g.pebble, {0.0f, 0.25f, 0.0f}, {0.5f, 0.25f, 0.4f}, 24, 12);
  for (int i = 0; i < 9; ++i) {
    const float s = 0.35f + 0.12f * static_cast<float>(i % 3);
    const float px = -3.6f + 0.85f * static_cast<float>(i), pz = 2.6f + 0.35f * static_cast<float>(i % 2);
    g.pebble_at.push_back({s, 0, 0, px, 0, s, 0, 0.0f, 0, 0, s, pz});
  }
  return g;
}

// --- Embree: the renderer's own ray tracer ---------------------------------------------------

// A committed Embree triangle mesh of a soup (nine floats a triangle, each corner its own vertex).
RTCGeometry soup_geometry(RTCDevice device, const std::vector<float>& positions) {
  const std::size_t n = positions.size() / 9;
  RTCGeometry mesh = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), 3 * n));
  auto* index = static_cast<unsigned*>(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), n));
  std::memcpy(v, positions.data(), positions.size() * sizeof(float));
  for (unsigned i = 0; i < 3 * n; ++i) index[i] = i;
  rtcCommitGeometry(mesh);
  return mesh;
}

struct Tracer {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  explicit Tracer(const Geometry& g) {
    device = rtcNewDevice(nullptr);
    scene = rtcNewScene(device);
    RTCGeometry mesh = soup_geometry(device, g.positions);
    rtcAttachGeometryByID(scene, mesh, 0);
    rtcReleaseGeometry(mesh);
    // The pebble once, in a scene of its own, placed by Embree instances (geometry 1, 2, ...).
    pebble = rtcNewScene(device);
    RTCGeometry shape = soup_geometry(device, g.pebble);
    rtcAttachGeometry(pebble, shape);
    rtcReleaseGeometry(shape);
    rtcCommitScene(pebble);
    for (std::size_t k = 0; k < g.pebble_at.size(); ++k) {
      RTCGeometry instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(instance, pebble);
      rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, g.pebble_at[k].data());
      rtcCommitGeometry(instance);
      rtcAttachGeometryByID(scene, instance, static_cast<unsigned>(k + 1));
      rtcReleaseGeometry(instance);
    }
    rtcCommitScene(scene);
  }
  ~Tracer() {
    rtcReleaseScene(scene);
    rtcReleaseScene(pebble);
    rtcReleaseDevice(device);
  }
  RTCScene pebble = nullptr;

  struct Hit {
    float t;
    unsigned triangle;      // of the main mesh, or of the pebble when instance >= 0
    int instance = -1;      // which pebble, or -1
  };
  // Nearest hit along o + t d, t in (near, far); triangle = RTC_INVALID_GEOMETRY_ID on a miss.
  Hit intersect(Vec3 o, Vec3 d, float near, float far) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit q{};
    q.ray = {o.x, o.y, o.z, near, d.x, d.y, d.z, 0.0f, far, 0xFFFFFFFFu, 0, 0};
    q.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &q);
    if (q.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {q.ray.tfar, RTC_INVALID_GEOMETRY_ID, -1};
    if (q.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) return {q.ray.tfar, q.hit.primID, static_cast<int>(q.hit.instID[0]) - 1};
    return {q.ray.tfar, q.hit.primID, -1};
  }
  bool occluded(Vec3 o, Vec3 d, float far) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{o.x, o.y, o.z, 0.0f, d.x, d.y, d.z, 0.0f, far, 0xFFFFFFFFu, 0, 0};
    rtcOccluded1(scene, &context, &ray);
    return ray.tfar < 0.0f;
  }
};

// --- Shading ---------------------------------------------------------------------------------

struct Renderer {
  const Geometry& g;
  const Tracer& tracer;
  const exao::api::Engine& ao;
  // Per-material AO distance: the room's objects take a shorter AO radius than its walls, from an
  // engine derived with Engine::with_settings (the scene is shared, not rebuilt).
  const exao::api::Engine& object_ao;
  int width = 960, height = 540, spp = 4, bounces = 2;
  Vec3 light{0.2f, 3.6f, 0.4f};  // a point light under the ceiling
  float light_power = 9.0f;
  float ambient = 0.8f;
  mutable std::atomic<int> ao_failures{0};  // queries that returned an error (none expected)

  Vec3 vertex(unsigned t, int j) const {
    const float* p = g.positions.data() + 9 * t + 3 * j;
    return {p[0], p[1], p[2]};
  }
  Vec3 face_normal(unsigned t) const {
    const Vec3 a = vertex(t, 0);
    return normalize(cross(vertex(t, 1) - a, vertex(t, 2) - a));
  }
  // A pebble triangle's normal: the model's (the placements scale uniformly, no rotation).
  Vec3 pebble_normal(unsigned t) const {
    const float* p = g.pebble.data() + 9 * t;
    return normalize(cross(Vec3{p[3] - p[0], p[4] - p[1], p[5] - p[2]}, Vec3{p[6] - p[0], p[7] - p[1], p[8] - p[2]}));
  }

  // Whether a point is on the room's shell (floor, ceiling, walls) rather than an object in it.
  static bool on_shell(Vec3 p, Vec3 n) {
    return (p.y < 0.001f && n.y > 0.9f) || p.y > 3.999f || std::abs(p.x) > 4.999f || std::abs(p.z) > 3.999f;
  }

  // Diffuse colour by where a point is: floor, ceiling, walls, and the room's objects.
  static Vec3 albedo(Vec3 p, Vec3 n) {
    if (p.y < 0.001f && n.y > 0.9f) return {0.62f, 0.45f, 0.30f};                   // wooden floor
    if (p.y > 3.999f) return {0.85f, 0.85f, 0.82f};                                  // ceiling
    if (std::abs(p.x) > 4.999f) return p.x < 0.0f ? Vec3{0.55f, 0.68f, 0.78f} : Vec3{0.80f, 0.78f, 0.72f};
    if (std::abs(p.z) > 3.999f) return {0.80f, 0.78f, 0.72f};                       // walls
    const Vec3 ball = p - Vec3{1.6f, 0.9f, 0.6f};
    if (dot(ball, ball) < 0.83f) return {0.75f, 0.30f, 0.22f};                       // the sphere
    if (p.x > 3.1f) return {0.70f, 0.70f, 0.70f};                                     // the column
    return {0.25f, 0.52f, 0.55f};                                                     // the boxes
  }

  // A cosine-weighted direction about n from two numbers in [0, 1).
  static Vec3 cosine_direction(Vec3 n, float u, float v) {
    const Vec3 t = normalize(std::abs(n.x) > 0.5f ? cross(n, {0, 1, 0}) : cross(n, {1, 0, 0}));
    const Vec3 b = cross(n, t);
    const float r = std::sqrt(u), phi = 6.2831853f * v;
    return r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0f, 1.0f - u)) * n;
  }

  static float hash_float(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return static_cast<float>((x ^ (x >> 31)) >> 40) * (1.0f / 16777216.0f);
  }

  // The first diffuse point along o + t d, mirrors followed: false when the path leaves.
  struct Diffuse {
    Vec3 p, n;
    bool pebble = false;
  };
  bool first_diffuse(Vec3 o, Vec3 d, Diffuse& out) const {
    for (int mirror_bounces = 0; mirror_bounces < 6; ++mirror_bounces) {
      const Tracer::Hit hit = tracer.intersect(o, d, 1e-4f, 1e30f);
      if (hit.triangle == RTC_INVALID_GEOMETRY_ID) return false;
      const Vec3 p = o + hit.t * d;
      const bool mirror = hit.instance < 0 && hit.triangle >= g.first_mirror;
      // The ball reflects with the true sphere's normal (smooth), everything else is flat.
      Vec3 n = hit.instance >= 0               ? pebble_normal(hit.triangle)
               : hit.triangle >= g.first_ball ? normalize(p - g.ball_centre)
                                               : face_normal(hit.triangle);
      if (dot(n, d) > 0.0f) n = -1.0f * n;  // the side the ray arrives from
      if (mirror) {
        o = p;
        d = d - 2.0f * dot(d, n) * n;
        continue;
      }
      out = {p, n, hit.instance >= 0};
      return true;
    }
    return false;
  }

  // Radiance arriving along o + t d. `key` identifies the path; depth 0 is the camera ray.
  Vec3 radiance(Vec3 o, Vec3 d, std::uint64_t key, int depth) const {
    Diffuse hit;
    if (!first_diffuse(o, d, hit)) return {0, 0, 0};
    return shade(hit.p, hit.n, hit.pebble, key, depth);
  }

  // A diffuse point: direct light with a shadow ray, ambient light times exao's AO, and (from
  // the camera's points only) one diffuse bounce, whose points get their own AO too.
  Vec3 shade(Vec3 p, Vec3 n, bool pebble, std::uint64_t key, int depth) const {
    const Vec3 colour = pebble ? Vec3{0.55f, 0.52f, 0.48f} : albedo(p, n);
    const Vec3 lift = p + 1e-4f * n;
    Vec3 to_light = light - p;
    const float distance2 = std::max(dot(to_light, to_light), 0.25f);  // no hot spot under the light
    to_light = (1.0f / std::sqrt(distance2)) * to_light;
    float direct = 0.0f;
    const float cosine = dot(n, to_light);
    if (cosine > 0.0f && !tracer.occluded(lift, to_light, std::sqrt(distance2) - 1e-3f)) {
      direct = light_power * cosine / (4.0f * 3.1415927f * distance2) * 3.1415927f;
    }
    // --- exao: the AO at this shading point, in one call (any thread, any point). ---
    const exao::api::Result<float> occlusion = (!pebble && on_shell(p, n) ? ao : object_ao).ao(p, n, key);
    if (!occlusion) ++ao_failures;
    const float open = occlusion.value_or(1.0f);
    Vec3 light_in = {direct + ambient * open, direct + ambient * open, direct + ambient * open};
    if (depth == 0 && bounces > 0) {
      Vec3 indirect{0, 0, 0};
      for (int b = 0; b < bounces; ++b) {
        const std::uint64_t bounce_key = key * 8 + static_cast<std::uint64_t>(b) + 1;
        const Vec3 dir = cosine_direction(n, hash_float(bounce_key), hash_float(~bounce_key));
        const Vec3 in = radiance(lift, dir, bounce_key, depth + 1);
        indirect = indirect + Vec3{std::min(in.x, 1.0f), std::min(in.y, 1.0f), std::min(in.z, 1.0f)};  // no fireflies
      }
      light_in = light_in + (0.6f / static_cast<float>(bounces)) * indirect;
    }
    return colour * light_in;
  }

  Vec3 pixel(int x, int y) const {
    const exao::api::Camera& c = g.camera;
    const Vec3 right = cross(c.forward, c.up);
    const float tan_half = std::tan(0.5f * c.yfov);
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    Vec3 sum{0, 0, 0};
    for (int s = 0; s < spp; ++s) {
      const std::uint64_t key = (static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(width) +
                                 static_cast<std::uint64_t>(x)) * static_cast<std::uint64_t>(spp) + static_cast<std::uint64_t>(s);
      const float jx = hash_float(key * 2), jy = hash_float(key * 2 + 1);  // anti-aliasing jitter
      const float sx = (2.0f * (static_cast<float>(x) + jx) / static_cast<float>(width) - 1.0f) * tan_half * aspect;
      const float sy = (1.0f - 2.0f * (static_cast<float>(y) + jy) / static_cast<float>(height)) * tan_half;
      sum = sum + radiance(c.eye, normalize(c.forward + sx * right + sy * c.up), key * 16, 0);
    }
    return (1.0f / static_cast<float>(spp)) * sum;
  }
};

// --- The AO pass, measured -------------------------------------------------------------------

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Runs body(i) for i in [0, count) on `threads` threads, in chunks; returns the wall time.
template <class Body>
double parallel_time(std::size_t count, unsigned threads, const Body& body) {
  std::atomic<std::size_t> next{0};
  const auto start = Clock::now();
  std::vector<std::thread> workers;
  for (unsigned w = 0; w < threads; ++w) {
    workers.emplace_back([&] {
      for (std::size_t first = next.fetch_add(64); first < count; first = next.fetch_add(64)) {
        for (std::size_t i = first; i < std::min(count, first + 64); ++i) body(i);
      }
    });
  }
  for (std::thread& worker : workers) worker.join();
  return seconds_since(start);
}

// The renderer's own AO loop: N cosine-weighted rays about n from its own sampler, 16 per
// rtcOccluded16 packet, tfar the material's AO distance. Returns the unblocked fraction.
float embree_ao(const Tracer& tracer, Vec3 p, Vec3 n, float distance, int samples, std::uint64_t key) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) RTCRay16 packet;
  alignas(64) int valid[16];
  const Vec3 o = p + 1e-4f * n;
  int blocked = 0;
  for (int first = 0; first < samples; first += 16) {
    for (int l = 0; l < 16; ++l) {
      const std::uint64_t k = key * 1024 + static_cast<std::uint64_t>(first + l);
      const Vec3 d = Renderer::cosine_direction(n, Renderer::hash_float(k), Renderer::hash_float(~k));
      packet.org_x[l] = o.x, packet.org_y[l] = o.y, packet.org_z[l] = o.z;
      packet.dir_x[l] = d.x, packet.dir_y[l] = d.y, packet.dir_z[l] = d.z;
      packet.tnear[l] = 0.0f, packet.tfar[l] = distance, packet.time[l] = 0.0f;
      packet.mask[l] = 0xFFFFFFFFu, packet.id[l] = 0, packet.flags[l] = 0;
      valid[l] = -1;
    }
    rtcOccluded16(valid, tracer.scene, &context, &packet);
    for (int l = 0; l < 16; ++l) blocked += packet.tfar[l] < 0.0f ? 1 : 0;
  }
  return 1.0f - static_cast<float>(blocked) / static_cast<float>(samples);
}

int measure_ao(const Renderer& renderer, const Tracer& tracer, float radius, float object_radius, int samples) {
  // The AO points of the camera's paths: one diffuse point per pixel (mirrors followed).
  struct Point {
    exao::api::Receiver receiver;
    bool object;
  };
  std::vector<Point> points;
  const exao::api::Camera& c = renderer.g.camera;
  const Vec3 right = cross(c.forward, c.up);
  const float tan_half = std::tan(0.5f * c.yfov);
  const float aspect = static_cast<float>(renderer.width) / static_cast<float>(renderer.height);
  for (int y = 0; y < renderer.height; ++y) {
    for (int x = 0; x < renderer.width; ++x) {
      const float sx = (2.0f * (static_cast<float>(x) + 0.5f) / static_cast<float>(renderer.width) - 1.0f) * tan_half * aspect;
      const float sy = (1.0f - 2.0f * (static_cast<float>(y) + 0.5f) / static_cast<float>(renderer.height)) * tan_half;
      Renderer::Diffuse hit;
      if (!renderer.first_diffuse(c.eye, normalize(c.forward + sx * right + sy * c.up), hit)) continue;
      const std::uint64_t key = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(renderer.width) + static_cast<std::uint64_t>(x);
      points.push_back({{hit.p, hit.n, key}, hit.pebble || !Renderer::on_shell(hit.p, hit.n)});
    }
  }
  std::vector<exao::api::Receiver> shell, objects;
  for (const Point& p : points) (p.object ? objects : shell).push_back(p.receiver);
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());

  // 1. exao's batch queries: one per material's engine.
  std::vector<float> shell_ao(shell.size()), object_ao(objects.size());
  const auto batch = [&] {
    const auto start = Clock::now();
    const exao::api::Status a = renderer.ao.ao(shell, shell_ao);
    const exao::api::Status b = renderer.object_ao.ao(objects, object_ao);
    if (!a || !b) std::fprintf(stderr, "exao_renderer: a batch failed\n");
    return seconds_since(start);
  };
  // 2. exao's single queries from the renderer's threads, as shade() asks.
  std::vector<float> single(points.size());
  const auto singles = [&] {
    return parallel_time(points.size(), threads, [&](std::size_t i) {
      const Point& p = points[i];
      single[i] = (p.object ? renderer.object_ao : renderer.ao).ao(p.receiver).value_or(1.0f);
    });
  };
  // 3. The renderer's own rtcOccluded16 loop.
  std::vector<float> own(points.size());
  const auto embree = [&] {
    return parallel_time(points.size(), threads, [&](std::size_t i) {
      const Point& p = points[i];
      own[i] = embree_ao(tracer, p.receiver.position, p.receiver.normal, p.object ? object_radius : radius, samples,
                         p.receiver.key);
    });
  };
  // Best of three runs each, interleaved, after one warm-up run of each.
  (void)batch(), (void)singles(), (void)embree();
  double t_batch = 1e30, t_single = 1e30, t_embree = 1e30;
  for (int run = 0; run < 3; ++run) {
    t_batch = std::min(t_batch, batch());
    t_single = std::min(t_single, singles());
    t_embree = std::min(t_embree, embree());
  }
  double mean_exao = 0.0, mean_own = 0.0;
  for (const float v : single) mean_exao += v;
  for (const float v : own) mean_own += v;
  const auto n = static_cast<double>(points.size());
  std::printf("points %zu (shell %zu, objects %zu) N %d simd %s threads %u\n", points.size(), shell.size(),
              objects.size(), samples, renderer.ao.info().simd, threads);
  std::printf("exao_batch_s %.4f exao_single_s %.4f rtcOccluded16_s %.4f\n", t_batch, t_single, t_embree);
  std::printf("ratio_batch %.2f ratio_single %.2f (rtcOccluded16 time / exao time)\n", t_embree / t_batch,
              t_embree / t_single);
  std::printf("mean_ao exao %.4f own_loop %.4f\n", mean_exao / n, mean_own / n);
  return 0;
}

// --- Output ----------------------------------------------------------------------------------

bool write_png(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) return false;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(file);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) {
    png_write_row(png, rgb.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width) * 3);
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return std::fclose(file) == 0;
}

std::uint8_t to_srgb8(float linear) {
  const float exposed = 0.85f * linear;
  const float mapped = exposed / (1.0f + 0.25f * exposed);  // gentle highlight roll-off
  const float v = std::pow(std::clamp(mapped, 0.0f, 1.0f), 1.0f / 2.2f);
  return static_cast<std::uint8_t>(std::lround(255.0f * v));
}

// The command line: -o, -W, -H, --spp, --samples, --radius, --object-radius, --measure-ao.
struct Args {
  std::string output = "renderer.png";
  int width = 960, height = 540, spp = 4, samples = 64;
  float radius = 1.0f, object_radius = 0.4f;
  bool measure = false;
};

// nullopt after printing the usage or the problem (exit status 2).
std::optional<Args> parse_args(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--measure-ao") {
      a.measure = true;
      --i;
      continue;
    }
    const std::string value = i + 1 < argc ? argv[i + 1] : "";
    if (flag == "-o") a.output = value;
    else if (flag == "-W") a.width = std::atoi(value.c_str());
    else if (flag == "-H") a.height = std::atoi(value.c_str());
    else if (flag == "--spp") a.spp = std::atoi(value.c_str());
    else if (flag == "--samples") a.samples = std::atoi(value.c_str());
    else if (flag == "--radius") a.radius = std::strtof(value.c_str(), nullptr);
    else if (flag == "--object-radius") a.object_radius = std::strtof(value.c_str(), nullptr);
    else {
      std::fprintf(stderr,
                   "usage: exao_renderer [-o out.png] [-W 960] [-H 540] [--spp 4] [--samples 64] [--radius 1] "
                   "[--object-radius 0.4] [--measure-ao]\n");
      return std::nullopt;
    }
  }
  if (a.width < 1 || a.height < 1 || a.spp < 1) {
    std::fprintf(stderr, "exao_renderer: -W, -H and --spp must be positive\n");
    return std::nullopt;
  }
  return a;
}

// exao: one engine for the whole scene, mirrors included (they occlude too), built once. The
// pebbles are instances of one mesh, read from the renderer's own arrays (nothing copied).
exao::api::Result<exao::api::Engine> build_engine(const Geometry& g, const Args& a) {
  exao::api::Mesh meshes[2];
  meshes[0].vertices = g.positions.data();
  meshes[0].vertex_count = g.positions.size() / 3;
  meshes[0].triangle_count = g.two_sided.size();
  meshes[0].two_sided = g.two_sided.data();
  meshes[1].vertices = g.pebble.data();
  meshes[1].vertex_count = g.pebble.size() / 3;
  meshes[1].triangle_count = g.pebble.size() / 9;  // two-sided (nullptr), like the tracer's
  std::vector<exao::api::Instance> instances{{0, nullptr}};
  for (const auto& at : g.pebble_at) instances.push_back({1, at.data()});
  exao::api::Options options;
  options.radius = a.radius;
  options.samples = a.samples;
  return exao::api::Engine::build(meshes, instances, options);
}

// The image as 8-bit sRGB, rows shared out to one thread per core.
std::vector<std::uint8_t> render_image(const Renderer& renderer, int width, int height) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  std::atomic<int> next_row{0};
  std::vector<std::thread> workers;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  for (unsigned w = 0; w < cores; ++w) {
    workers.emplace_back([&] {
      for (int y = next_row++; y < height; y = next_row++) {
        for (int x = 0; x < width; ++x) {
          const Vec3 c = renderer.pixel(x, y);
          std::uint8_t* out = rgb.data() + (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3;
          out[0] = to_srgb8(c.x);
          out[1] = to_srgb8(c.y);
          out[2] = to_srgb8(c.z);
        }
      }
    });
  }
  for (std::thread& worker : workers) worker.join();
  return rgb;
}

}  // namespace

int main(int argc, char** argv) {
  const std::optional<Args> args = parse_args(argc, argv);
  if (!args) return 2;
  const Args& a = *args;
  const Geometry g = make_scene();
  const Tracer tracer(g);
  exao::api::Result<exao::api::Engine> engine = build_engine(g, a);
  if (!engine) {
    std::fprintf(stderr, "exao_renderer: %s\n", engine.error().message.c_str());
    return 1;
  }
  exao::api::QuerySettings objects;
  objects.radius = a.object_radius;
  exao::api::Result<exao::api::Engine> object_engine = engine->with_settings(objects);
  if (!object_engine) {
    std::fprintf(stderr, "exao_renderer: --object-radius: %s\n", object_engine.error().message.c_str());
    return 1;
  }

  Renderer renderer{g, tracer, *engine, *object_engine};
  renderer.width = a.width;
  renderer.height = a.height;
  renderer.spp = a.spp;
  if (a.measure) return measure_ao(renderer, tracer, a.radius, a.object_radius, a.samples);
  const std::vector<std::uint8_t> rgb = render_image(renderer, a.width, a.height);
  if (renderer.ao_failures > 0) std::fprintf(stderr, "exao_renderer: %d AO queries failed\n", renderer.ao_failures.load());
  if (!write_png(a.output, a.width, a.height, rgb)) {
    std::fprintf(stderr, "exao_renderer: %s: cannot write\n", a.output.c_str());
    return 1;
  }
  std::printf("%s: %d x %d, %d samples per pixel, AO N = %d, r = %g (objects %g, %s backend)\n", a.output.c_str(), a.width,
              a.height, a.spp, a.samples, static_cast<double>(a.radius), static_cast<double>(a.object_radius), "auto");
  return 0;
}
