#pragma once
// exao: exact ray-cast ambient occlusion (Laine & Karras 2010, "Two Methods for Fast Ray-Cast
// Ambient Occlusion") as a drop-in replacement for the AO ray loop of an offline renderer.
//
// Build an Engine once from a scene, then ask it for the AO (or the per-ray occlusion mask) at
// any point: the answer is, bit for bit, what casting the engine's N shadow rays with a ray
// tracer gives (the `embree` backend does exactly that), computed all N rays at once.
//
//     exao::api::Options options;
//     options.radius = 0.5f;                                  // world units
//     auto engine = exao::api::Engine::build(mesh, options);  // once
//     if (!engine) fail(engine.error().message);
//     float ao = engine->ao(position, normal, key).value_or(1.0f);  // any thread, any time
//
// Conventions (the project's DESIGN.md, sections 1 and 3):
//  - AO = 1 - (blocked rays) / N: 1 is fully open, 0 fully occluded (glTF occlusion semantics).
//  - The rays of a receiver start at p' = p + origin_offset * n/|n| and go in N directions of a
//    shared cosine-weighted hemisphere pattern about n, slightly tilted and rotated by a
//    pseudo-random amount chosen by the receiver's `key`: the same key gives the same rays in
//    every backend and run. Use the pixel, vertex or texel index, or any number that identifies
//    the shading point; different keys decorrelate the noise of neighbouring points.
//  - A ray is blocked by a triangle when it meets it within its length l_i * radius, l_i in
//    (0, 1] (all 1 with constant falloff). A one-sided triangle blocks only rays arriving at its
//    front face, whose vertices are counter-clockwise (glTF); two-sided triangles block both.
//
// Errors: every function is noexcept. Bad input returns an Error (a StatusCode and a one-line
// message naming the argument); nothing is thrown across this boundary, printed, or fatal; an
// allocation failure returns StatusCode::OutOfMemory. Only reading the value of a Result that
// holds an error (or its error when it holds a value) throws, BadResultAccess, in the caller's
// code: a precondition violation that must not pass silently in a Release build.
//
// Radius: every radius up to 1e17 is exact, far beyond the scene too (a renderer's "unbounded"):
// no segment from a receiver reaches geometry past the farthest corner of the occluders' box,
// so the masks cap every ray there, which hits the same triangles.
//
// Threads: an Engine is immutable after build. Any number of threads may call its const
// functions at the same time, on the same engine, with no locking by the caller. Single queries
// run on the calling thread; batch queries run on the engine's own worker pool
// (Options::threads) and return when done.
//
// Requires C++20. This header includes only the standard library.

#include <array>
#include <bit>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "exao/export.h"

namespace exao::api {

// --- Version ----------------------------------------------------------------------------------

inline constexpr int kVersionMajor = 0;
inline constexpr int kVersionMinor = 1;
inline constexpr int kVersionPatch = 0;

/// The version of the library actually loaded, "MAJOR.MINOR.PATCH" (static storage).
[[nodiscard]] EXAO_API const char* version() noexcept;

// --- Errors -----------------------------------------------------------------------------------

/// What went wrong. The numbers equal the C API's exao_status values.
enum class StatusCode : int {
  Ok = 0,
  InvalidArgument = 1,  // a null pointer, a size that does not match, a value out of range, NaN
  OutOfMemory = 2,      // an allocation failed; the engine (if any) is unchanged and usable
  FileError = 3,        // a scene file is missing, unreadable or malformed
  BackendError = 4,     // Embree refused (device creation, scene build)
  InternalError = 5,    // a bug in exao: please report the message
  Cancelled = 6,        // a batch's progress callback returned false
  CallbackError = 7,    // a callback the caller gave threw; the message holds its what()
};

/// A short English text for the code, e.g. "invalid argument" (static storage; never null).
[[nodiscard]] EXAO_API const char* status_text(StatusCode code) noexcept;

/// An error: the code and one line naming the argument or file and the problem.
struct Error {
  StatusCode code = StatusCode::InternalError;
  std::string message;
};

/// Thrown by Result::value() (and its * and ->) on an error, and by error() on a value, as
/// std::expected throws bad_expected_access: a precondition violation, loud in every build type
/// (a Release client must not read a value that is not there). what() is the error's message.
class BadResultAccess : public std::logic_error {
 public:
  explicit BadResultAccess(const Error& error)
      : std::logic_error("exao: value() of a failed Result: " + error.message), error_(error) {}
  BadResultAccess() : std::logic_error("exao: error() of a Result that holds a value") {}
  /// The error the Result held (code Ok when error() was called on a value).
  [[nodiscard]] const Error& error() const noexcept { return error_; }

 private:
  Error error_{StatusCode::Ok, {}};
};

/// A value of T or an Error: the subset of C++23 std::expected that callers use. Accessing the
/// value of an error, or the error of a value, throws BadResultAccess (the only exception this
/// header's types throw; the library's functions themselves never throw).
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::in_place_index<0>, std::move(value)) {}  // NOLINT: implicit, like expected
  Result(Error error) : v_(std::in_place_index<1>, std::move(error)) {}  // NOLINT

  [[nodiscard]] bool has_value() const noexcept { return v_.index() == 0; }
  explicit operator bool() const noexcept { return has_value(); }
  /// StatusCode::Ok with a value, else the error's code.
  [[nodiscard]] StatusCode code() const noexcept { return has_value() ? StatusCode::Ok : std::get<1>(v_).code; }

  [[nodiscard]] T& value() & { check(); return *std::get_if<0>(&v_); }
  [[nodiscard]] const T& value() const& { check(); return *std::get_if<0>(&v_); }
  [[nodiscard]] T&& value() && { check(); return std::move(*std::get_if<0>(&v_)); }
  [[nodiscard]] T& operator*() & { return value(); }
  [[nodiscard]] const T& operator*() const& { return value(); }
  [[nodiscard]] T&& operator*() && { return std::move(*this).value(); }
  [[nodiscard]] T* operator->() { return &value(); }
  [[nodiscard]] const T* operator->() const { return &value(); }
  /// The value, or `fallback` on an error.
  template <class U>
  [[nodiscard]] T value_or(U&& fallback) const& {
    return has_value() ? *std::get_if<0>(&v_) : static_cast<T>(std::forward<U>(fallback));
  }
  [[nodiscard]] const Error& error() const {
    if (has_value()) throw BadResultAccess();
    return *std::get_if<1>(&v_);
  }

 private:
  void check() const {
    if (!has_value()) throw BadResultAccess(*std::get_if<1>(&v_));
  }
  std::variant<T, Error> v_;
};

/// Success or an Error, for functions with no value to return.
class [[nodiscard]] Status {
 public:
  Status() = default;  // success
  Status(Error error) : error_(std::move(error)) {}  // NOLINT: implicit, like unexpected

  [[nodiscard]] bool ok() const noexcept { return !error_; }
  explicit operator bool() const noexcept { return ok(); }
  [[nodiscard]] StatusCode code() const noexcept { return error_ ? error_->code : StatusCode::Ok; }
  /// The error; throws BadResultAccess when ok().
  [[nodiscard]] const Error& error() const {
    if (!error_) throw BadResultAccess();
    return *error_;
  }

 private:
  std::optional<Error> error_;
};

// --- Geometry ---------------------------------------------------------------------------------

/// A point or vector, world units. Standard layout: three floats, like float[3].
struct Vec3 {
  float x = 0.0f;
  float y = 0.0f;
  float z = 0.0f;
};

/// A triangle mesh in the caller's own arrays, read once by Engine::build (which keeps its own
/// compact copy: the arrays may be freed or changed as soon as build returns).
///
/// Triangle t has the vertices indices[3t], indices[3t+1], indices[3t+2] (or, without indices,
/// the vertices 3t, 3t+1, 3t+2: a triangle soup). Its front face is the one where these appear
/// counter-clockwise (glTF): normal = cross(v1 - v0, v2 - v0).
struct Mesh {
  /// Position of vertex i: three floats (x, y, z), world units (or model units, see transform),
  /// at byte offset i * vertex_stride from `vertices`. Must be 4-byte aligned; may point into an
  /// interleaved vertex buffer. Every vertex a triangle uses must be finite.
  const float* vertices = nullptr;
  std::size_t vertex_count = 0;
  /// Bytes from one vertex to the next: a multiple of 4, at least 12.
  std::size_t vertex_stride = 3 * sizeof(float);
  /// Triangle t's three vertex indices at byte offset t * index_stride from `indices`, each
  /// < vertex_count. nullptr: no index buffer (then 3 * triangle_count <= vertex_count).
  const std::uint32_t* indices = nullptr;
  /// Bytes from one triangle's indices to the next: a multiple of 4, at least 12.
  std::size_t index_stride = 3 * sizeof(std::uint32_t);
  std::size_t triangle_count = 0;
  /// Per triangle, triangle_count bytes: 0 one-sided, anything else two-sided. nullptr: every
  /// triangle of this mesh is two-sided (what a ray tracer without a back-face test does).
  /// Options::sidedness One or Two overrides both.
  const std::uint8_t* two_sided = nullptr;
  /// Optional placement: 12 floats, a row-major 3x4 matrix M, world = M * (x, y, z, 1), for
  /// instanced meshes. nullptr: the vertices are in world units already. Must be finite.
  const float* transform = nullptr;
};

/// An id that names no object: Receiver::excluded_object's default.
inline constexpr std::uint32_t kNoObject = 0xFFFFFFFFu;

/// One placement of a mesh (Engine::build with instances): meshes[mesh] at `transform`, as
/// many times as the caller likes, from the same arrays (the caller copies nothing).
///
/// Memory: the engine flattens every placement into world-space triangles, since the mask
/// backends' BVH is one level. The reference (Embree) reads the same flattened floats, which is
/// what keeps every backend's rays and bits identical; Embree instances would apply the
/// transform inside Embree, in floats no mask sees. Each placed triangle costs what a triangle
/// of its own costs: about 0.8 KiB of resident memory with the default auto backend, measured
/// right after build (a 10k-triangle mesh placed 101 times: +820 MiB against placed once; the
/// BVH's triangles, packed and lane copies, Embree's buffers and BVH, and what the build's
/// temporaries leave resident). A two-level BVH that stores a mesh once is not there yet.
struct Instance {
  std::size_t mesh = 0;  // index into build's meshes
  /// 12 floats, a row-major 3x4 matrix M: world = M * (the mesh's vertex after its own
  /// Mesh::transform, 1). nullptr: identity. Must be finite. Read during build and refit only.
  const float* transform = nullptr;
};

/// A pinhole camera of a scene file (or of a built-in scene).
struct Camera {
  std::string name;
  Vec3 eye;                      // world units
  Vec3 forward{0.0f, 0.0f, -1.0f};  // unit
  Vec3 up{0.0f, 1.0f, 0.0f};        // unit, orthogonal to forward
  float yfov = 0.8f;                // vertical field of view, radians, in (0, pi)
  float aspect = 0.0f;              // width / height when the file fixes it, else 0
};

/// A scene read from a file or made by a built-in generator, as flat arrays the caller owns:
/// for a renderer that wants exao's loaders (glTF, OBJ, PLY, OFF, STL) or its test scenes.
struct SceneData {
  std::string name;
  std::vector<float> positions;          // 9 floats per triangle (v0, v1, v2), world units
  std::vector<std::uint8_t> two_sided;   // per triangle: 1 blocks rays from both sides
  std::vector<std::int32_t> material;    // per triangle: the file's material index, -1 for none
  std::vector<Camera> cameras;           // the file's cameras, in file order
  std::vector<std::string> notes;        // one line each: what the loader skipped, and why

  [[nodiscard]] std::size_t triangle_count() const noexcept { return two_sided.size(); }
  /// A Mesh that views these arrays (a soup, with per-triangle sidedness). Valid while this
  /// SceneData lives and its vectors are not resized.
  [[nodiscard]] Mesh mesh() const noexcept {
    Mesh m;
    m.vertices = positions.data();
    m.vertex_count = positions.size() / 3;
    m.triangle_count = two_sided.size();
    m.two_sided = two_sided.data();
    return m;
  }
};

/// Reads `name_or_path`: a built-in scene ("room", "plane-pair", "sphere-on-plane") or a
/// `.gltf`/`.glb`/`.obj`/`.ply`/`.off`/`.stl` file (by extension, case-insensitive). glTF
/// triangles are one-sided unless their material is doubleSided; other formats are two-sided.
/// Triangles of zero area or with non-finite vertices are skipped and said so in `notes`.
/// Errors: FileError naming the file (missing, unreadable, malformed, no triangle left),
/// InvalidArgument for an empty name, OutOfMemory.
[[nodiscard]] EXAO_API Result<SceneData> load_scene(std::string_view name_or_path) noexcept;

/// Names of the built-in scenes; the first ("room") is the default of the exao program. Empty
/// only if the allocation of the list fails.
[[nodiscard]] EXAO_API std::vector<std::string> builtin_scene_names() noexcept;

// --- Options ----------------------------------------------------------------------------------

/// Which algorithm computes the masks. Auto (the default) gives Embree's answer on every ray,
/// and is never meant to be slower than Embree: masks first, Embree for the rays they do not
/// decide cheaply or surely. bvh and brute are the paper's method alone, bit-identical to each
/// other; with MaskMode::Exact they agree with embree on all rays but a few that graze an edge.
enum class Backend : int {
  Bvh = 0,     // paper Sec. 5: BVH traversal with occlusion-ordered culling; the fast default
  Brute = 1,   // OR of every nearby triangle's mask: the slow definition bvh reproduces
  Embree = 2,  // N rtcOccluded rays per receiver: the reference ray caster
  Raster = 3,  // paper Sec. 4: serves only the pixels of a camera image (the exao program's
               // render and bench), never arbitrary points: Engine::build refuses it with
               // InvalidArgument naming options.backend
  Auto = 4,    // bvh's masks under a cost model, then Embree's rays (exact masks only)
};

/// Where the plane masks of bvh and brute come from (ignored by embree).
enum class MaskMode : int {
  Lut = 0,    // the paper's look-up table: >= 99% of rays agree with a ray tracer
  Exact = 1,  // an exact test of the N sample points: no discretisation error, and the faster
              // one on every instruction set measured (the default)
};

/// How occlusion fades with the distance D to the occluder (the paper's Eq. 1, rho(D)):
/// constant rho = 1 for D < r; linear rho = 1 - D/r; quadratic rho = (1 - D/r)^2. Realised as
/// ray lengths drawn from the falloff, so AO stays "1 - blocked / N".
enum class Falloff : int { Constant = 0, Linear = 1, Quadratic = 2 };

/// Which triangles block rays from behind.
enum class Sidedness : int {
  Auto = 0,  // as the mesh (Mesh::two_sided) or the file (glTF doubleSided) says
  One = 1,   // every triangle one-sided
  Two = 2,   // every triangle two-sided
};

/// How the embree backend hands rays to Embree in batch queries (single queries cast single
/// rays). The answer is the same; the speed differs.
enum class EmbreeRays : int { Single = 0, Packet4 = 1, Packet8 = 2, Packet16 = 3 };

/// Engine settings. Every field has a default; Engine::build checks them all and names the
/// first bad one in its error (InvalidArgument).
struct Options {
  /// r: the length of the longest shadow ray, world units, finite, > 0 and at most 1e17.
  /// nullopt: 5% of the scene's bounding-box diagonal (the exao program's default).
  std::optional<float> radius;
  /// N: rays per receiver, a multiple of 32 in [32, 1024]. A mask holds N bits.
  int samples = 128;
  Falloff falloff = Falloff::Constant;
  /// Seed of the shared sample pattern; the same seed gives the same rays everywhere.
  std::uint64_t pattern_seed = 0x65CA0;
  Sidedness sidedness = Sidedness::Auto;
  MaskMode mask_mode = MaskMode::Exact;
  /// eps: rays start at p + eps * n/|n|, world units, finite, >= 0 and at most 1e17: lifts
  /// rays off the receiver's own surface. nullopt (the default): the point's own scale,
  ///     eps(p) = max(1e-6, 1e-4 * max(|p.x|, |p.y|, |p.z|))   world units,
  /// about 840 float ulps of p's largest coordinate, so a triangle added far away changes no
  /// receiver's rays. (The exao program's default is 1e-4 of the scene's bounding-box diagonal,
  /// DESIGN.md section 1; give that value here to get `exao query`'s rays.)
  std::optional<float> origin_offset;
  /// Worker threads of batch queries (and of the build), from 0 to 256 (or 4x the cores, if
  /// more: oneTBB's ceiling); 0: one per core.
  int threads = 0;
  Backend backend = Backend::Auto;
  /// Look-up table cells per side R (MaskMode::Lut), 0 or in [4, 256]: 0 picks the default
  /// for N (64 to 128, tens of MiB). Memory: R^3 * B / 8 bytes, B = N rounded up to a power
  /// of two >= 64. Built once per engine, in about a second on a few cores.
  int table_resolution = 0;
  /// BVH children per node: 2 or 4.
  int bvh_branching = 4;
  /// Ray submission of the embree backend's batch queries.
  EmbreeRays embree_rays = EmbreeRays::Packet16;
};

// --- Queries ----------------------------------------------------------------------------------

/// A point that receives occlusion.
struct Receiver {
  Vec3 position;              // world units, finite
  Vec3 normal{0.0f, 0.0f, 1.0f};  // the side rays leave from: finite, need not be unit; its
                              // squared length must be a normal float (|n| in about [1e-19, 1e19])
  std::uint64_t key = 0;      // picks the pattern's jitter (see the top of this file)
  /// An object whose triangles block none of this receiver's rays, in every backend (Embree's
  /// filter skips them too): the shaded object itself, say. Objects are the meshes of
  /// Engine::build (index into meshes) or, when built with instances, the instances (index into
  /// instances). kNoObject: none. An id that names no object excludes nothing.
  std::uint32_t excluded_object = kNoObject;
};

/// One shadow ray of a receiver, world space: it starts at the receiver's ray origin p'.
struct ShadowRay {
  Vec3 direction;       // unit
  float length = 0.0f;  // world units, in (0, radius]
};

/// The occlusion mask of one receiver: bit i set means shadow ray i is blocked. Bits at or past
/// `samples` are zero.
struct RayMask {
  static constexpr int kMaxSamples = 1024;
  int samples = 0;                                       // N
  std::array<std::uint64_t, kMaxSamples / 64> words{};   // bit i: words[i / 64] >> (i % 64)

  /// Whether ray i, i in [0, samples), is blocked.
  [[nodiscard]] bool blocked(int i) const noexcept {
    assert(i >= 0 && i < samples);
    return ((words[static_cast<std::size_t>(i) / 64] >> (i % 64)) & 1u) != 0;
  }
  /// Number of blocked rays, in [0, samples].
  [[nodiscard]] int blocked_count() const noexcept {
    int n = 0;
    for (const std::uint64_t w : words) n += std::popcount(w);
    return n;
  }
  /// 1 - blocked_count / samples, in [0, 1] (the same float Engine::ao returns).
  [[nodiscard]] float ao() const noexcept {
    return samples > 0 ? 1.0f - static_cast<float>(blocked_count()) / static_cast<float>(samples) : 1.0f;
  }
};

/// What an engine was built with, after defaults were resolved.
struct EngineInfo {
  Backend backend = Backend::Auto;
  MaskMode mask_mode = MaskMode::Exact;
  Falloff falloff = Falloff::Constant;
  int samples = 0;                 // N
  std::size_t mask_words = 0;      // 64-bit words per mask in batch output: (N + 63) / 64
  float radius = 0.0f;             // r, world units
  float origin_offset = 0.0f;      // eps, world units: the offset given, or the default's floor 1e-6
  float origin_offset_per_magnitude = 0.0f;  // 1e-4 with the default offset, then the offset at p is
                                   // max(origin_offset, origin_offset_per_magnitude * max_k |p_k|);
                                   // 0 when an offset was given
  int threads = 0;                 // worker threads of batch queries
  std::size_t triangles = 0;       // triangles kept (non-zero area)
  std::size_t two_sided_triangles = 0;
  std::size_t zero_area_skipped = 0;  // triangles of the meshes dropped for zero area (they block nothing)
  std::size_t beyond_limit_skipped = 0;  // ... dropped for a vertex beyond +-1e17 (Embree's limit; with
                                   // Engine::open, non-finite vertices of the file too). When every
                                   // triangle is dropped, build refuses the scene saying why.
  Vec3 bounds_lo;                  // the scene's bounding box, world units
  Vec3 bounds_hi;
  int table_resolution = 0;        // look-up table cells per side (0: no table)
  std::size_t table_bytes = 0;     // memory of the look-up table
  const char* simd = "";           // the instruction set the mask kernels run (chosen at run time, not
                                   // the one the library was compiled for): "scalar", "sse2", "sse4",
                                   // "avx2" or "avx512" (the CPU's best, or what EXAO_ISA says);
                                   // "none" for Backend::Embree, which runs no mask kernel
};

/// Work counters of batch queries with the bvh backend (zero for the others).
struct WorkStats {
  std::uint64_t receivers = 0;
  std::uint64_t nodes_visited = 0;       // BVH nodes whose children were tested
  std::uint64_t triangles_tested = 0;    // triangle masks computed
  std::uint64_t triangles_blocking = 0;  // triangles that blocked at least one new ray
};

/// Optional settings of one batch query.
struct BatchOptions {
  /// Called with (done, total) receivers from worker threads, possibly concurrently; must be
  /// thread-safe. Return true to go on, false to cancel: the batch then stops as soon as the
  /// workers notice and returns StatusCode::Cancelled (outputs are left partly written). An
  /// exception it throws stops the batch the same way and comes back as
  /// StatusCode::CallbackError with the exception's what() in the message.
  std::function<bool(std::size_t done, std::size_t total)> progress;
  /// When not empty, one entry per receiver (else InvalidArgument): StatusCode::Ok for a
  /// receiver that was computed, InvalidArgument for a bad one (see below). Empty: not reported.
  std::span<StatusCode> statuses;
  /// When not null, the bvh backend adds its work counters to *stats (the caller's object; not
  /// synchronised: give each concurrent batch its own).
  WorkStats* stats = nullptr;
  /// Overrides Options::embree_rays for this batch.
  std::optional<EmbreeRays> embree_rays;
};

/// Settings of queries that differ from an engine's own (Engine::with_settings): a renderer's
/// per-material AO distance, or fewer rays for a preview. nullopt keeps the engine's.
struct QuerySettings {
  std::optional<float> radius;         // r, world units: as Options::radius
  std::optional<float> origin_offset;  // eps, world units: as Options::origin_offset
  std::optional<int> samples;          // N: as Options::samples
  /// The caller's own ray directions instead of the shared pattern (a renderer's sampler):
  /// N = directions.size() unit vectors (normalised by exao) in the receiver frame, +z along
  /// the normal, each with z > 0; N a multiple of 32 in [32, 1024] (samples, if given, must
  /// equal it). Bit i of every mask is direction i. Every receiver's frame is still turned by
  /// its key's small tilt and rotation (rays() gives the world rays). Copied by with_settings.
  /// Empty: the engine's pattern.
  /// Cost: the exact masks need the directions only, so no table is built in MaskMode::Exact
  /// (MaskMode::Lut builds one, about a second). Making the engine copies them and computes
  /// the cone of every run of 16 consecutive directions (microseconds; examples/README figures):
  /// the masks are exact in any order, and fastest when each run of 16 is a compact cone, as
  /// the shared pattern's are; a random order costs speed, never bits.
  std::span<const Vec3> directions;
  /// Lengths of the directions' rays as fractions of r, in (0, 1]: empty, all 1; else one per
  /// direction (a falloff of the caller's).
  std::span<const float> lengths;
};

/// An AO engine: the scene's triangles in the backend's structure, the sample pattern and the
/// look-up table, built once. Move-only; a moved-from engine answers every query with
/// InvalidArgument. Immutable after build: every const member may be called from any number of
/// threads at once.
class EXAO_API Engine {
 public:
  /// Builds from the caller's meshes (copied: see Mesh), all in one scene. Errors:
  /// InvalidArgument naming the mesh, triangle or option (null arrays, bad strides, an index out
  /// of range, a non-finite vertex, no triangle of non-zero area, a bad option); BackendError
  /// (Embree); OutOfMemory. Time: the BVH (Embree's SAH builder) plus, in MaskMode::Lut, the
  /// look-up table; the built-in room (~4k triangles) builds in about a second at N = 128.
  [[nodiscard]] static Result<Engine> build(std::span<const Mesh> meshes, const Options& options = {}) noexcept;
  [[nodiscard]] static Result<Engine> build(const Mesh& mesh, const Options& options = {}) noexcept {
    return build(std::span<const Mesh>(&mesh, 1), options);
  }
  /// Builds from placements of the meshes (Instance): the scene is every instance's mesh at
  /// its transform, and the objects a receiver can exclude are the instances. A mesh no
  /// instance names is not in the scene. Errors: as above, and InvalidArgument naming
  /// instances[i] (a mesh index out of range, a non-finite transform) or an empty list.
  [[nodiscard]] static Result<Engine> build(std::span<const Mesh> meshes, std::span<const Instance> instances,
                                            const Options& options = {}) noexcept;
  /// load_scene(name_or_path), then build: the same engine the exao program uses for that scene.
  [[nodiscard]] static Result<Engine> open(std::string_view name_or_path, const Options& options = {}) noexcept;

  Engine(Engine&&) noexcept;
  Engine& operator=(Engine&&) noexcept;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;
  ~Engine();

  /// An engine over the same scene with other settings: it shares this engine's BVH, Embree
  /// scene and triangles (nothing of the scene is copied or rebuilt, and it stays valid after
  /// this engine is destroyed), with its own rays. Sample patterns are cached by N, falloff and
  /// seed, so making one costs the pattern's sample arrays (microseconds) and, with
  /// MaskMode::Lut, a plane table (about a second): make one per material or setting once, and
  /// query it like any engine. Errors: InvalidArgument naming settings.radius,
  /// settings.origin_offset or settings.samples, or the engine when it is empty.
  [[nodiscard]] Result<Engine> with_settings(const QuerySettings& settings) const noexcept;

  /// Refit after a deformation or an animation: the same meshes (and instances, if build had
  /// them) with the same topology, new vertex positions or transforms: the same counts, mesh
  /// indices, index buffers' values and sidedness; the arrays may be other ones. Embree refits
  /// its BVH, the mask backends recompute their triangles and their BVH's boxes and spheres
  /// (same tree), and the answers are then those of a fresh build, bit for bit, for every
  /// backend. Triangles that build dropped (zero area) stay out; one that collapses to zero
  /// area blocks nothing. The radius and offset keep their values. It moves the scene of every
  /// engine made from this one by with_settings too (they share it). Not thread-safe: no query
  /// of those engines may run during it. About a rebuild's time for Embree's part and a few ms
  /// per 100k triangles for the masks' (no SAH build). Errors: InvalidArgument naming what
  /// differs from build or a non-finite vertex (the engine is then unchanged), or the engine
  /// when it is empty; BackendError (Embree).
  [[nodiscard]] Status refit(std::span<const Mesh> meshes, std::span<const Instance> instances = {}) noexcept;

  /// The resolved settings and sizes (for an empty, moved-from engine: all zero).
  [[nodiscard]] const EngineInfo& info() const noexcept;
  /// N, the rays per receiver (0 for a moved-from engine).
  [[nodiscard]] int samples() const noexcept { return info().samples; }
  /// 64-bit words per mask in masks(): (N + 63) / 64.
  [[nodiscard]] std::size_t mask_words() const noexcept { return info().mask_words; }

  // Single queries: computed on the calling thread (no allocation with bvh and brute); about
  // 5 to 25 microseconds each at N = 64 to 256 on the built-in room (api_benchmark).

  /// AO at one receiver, in [0, 1]. Errors: InvalidArgument for a non-finite position, or a
  /// normal that is non-finite or too short to normalise.
  [[nodiscard]] Result<float> ao(const Receiver& receiver) const noexcept;
  [[nodiscard]] Result<float> ao(Vec3 position, Vec3 normal, std::uint64_t key) const noexcept {
    return ao(Receiver{position, normal, key});
  }
  /// The occlusion mask of one receiver. When `rays` is not empty it must hold exactly N
  /// entries and receives ray i's world direction and length (bit i of the mask says whether
  /// that ray is blocked): for callers who shade per ray (bent normals, environment lighting).
  /// Errors: as ao(), and InvalidArgument when rays.size() is neither 0 nor N.
  [[nodiscard]] Result<RayMask> mask(const Receiver& receiver, std::span<ShadowRay> rays = {}) const noexcept;
  /// The N shadow rays of a receiver without casting them: their common origin p' (world
  /// units) and, in `rays` (exactly N entries), each direction and length. Errors: as mask().
  [[nodiscard]] Status rays(const Receiver& receiver, Vec3& origin, std::span<ShadowRay> rays) const noexcept;

  // Batch queries: parallel on the engine's worker threads (Options::threads); the receivers
  // are visited in a cache-friendly order and the results written in the caller's order.
  // Every receiver is checked first. A bad one (as for a single query: a non-finite or too
  // distant position, a normal that cannot be normalised) does not stop the others: its AO is
  // NaN (its mask all zero words), its entry of BatchOptions::statuses is InvalidArgument, and
  // every other receiver is computed; the batch then returns InvalidArgument naming the first
  // bad receiver's index and how many there were. Sizes that do not match, a moved-from engine,
  // Cancelled and CallbackError fail the whole batch.

  /// ao[i] = AO of receivers[i]; ao.size() must equal receivers.size().
  [[nodiscard]] Status ao(std::span<const Receiver> receivers, std::span<float> ao,
                          const BatchOptions& batch = {}) const noexcept;
  /// Masks of the receivers, mask_words() words each, receiver i at words[i * mask_words()];
  /// words.size() must equal receivers.size() * mask_words().
  [[nodiscard]] Status masks(std::span<const Receiver> receivers, std::span<std::uint64_t> words,
                             const BatchOptions& batch = {}) const noexcept;

  struct Impl;  // opaque

 private:
  explicit Engine(std::unique_ptr<Impl> impl) noexcept;
  std::unique_ptr<Impl> impl_;
};

}  // namespace exao::api
