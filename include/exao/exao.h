/* exao: exact ray-cast ambient occlusion (Laine & Karras 2010), C API.
 *
 * The same engine as the C++ API (exao/exao.hpp), for C and for foreign-function callers: opaque
 * handles, plain structs, explicit status codes. Read exao/exao.hpp's opening comment for what
 * is computed (AO = 1 - blocked / N, rays from p + eps * n, receiver keys, sidedness).
 *
 *     exao_options options;
 *     exao_options_init(&options);
 *     options.radius = 0.5f;
 *     exao_engine* engine = NULL;
 *     char message[256];
 *     if (exao_engine_create(&mesh, 1, &options, &engine, message, sizeof message) != EXAO_OK) ...
 *     float ao;
 *     exao_ao(engine, position, normal, key, &ao);   // any thread
 *     exao_engine_destroy(engine);
 *
 * Errors: every function returns an exao_status (or a value that cannot fail). Nothing is
 * printed, nothing aborts, no C++ exception crosses this boundary. The message of a failed
 * call is returned through the caller's buffer (creation functions) or exao_engine_last_error
 * (queries). On an error, outputs are left unchanged unless the function says otherwise.
 *
 * Threads: an engine is immutable after creation; any number of threads may query the same
 * engine at once. exao_engine_destroy must not run concurrently with a query on that engine.
 *
 * Strings are UTF-8 (file names as the operating system takes them), NUL-terminated. Units are
 * the scene's world units throughout. This header includes only <stddef.h> and <stdint.h>. */
#ifndef EXAO_EXAO_H
#define EXAO_EXAO_H

#include <stddef.h>
#include <stdint.h>

#include "exao/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* --- Status ------------------------------------------------------------------------------- */

/* Equal to exao::api::StatusCode. */
typedef enum exao_status {
  EXAO_OK = 0,
  EXAO_INVALID_ARGUMENT = 1, /* null pointer, size mismatch, value out of range, NaN */
  EXAO_OUT_OF_MEMORY = 2,    /* an allocation failed; the engine (if any) is unchanged */
  EXAO_FILE_ERROR = 3,       /* a scene file is missing, unreadable or malformed */
  EXAO_BACKEND_ERROR = 4,    /* Embree refused (device creation, scene build) */
  EXAO_INTERNAL_ERROR = 5,   /* a bug in exao: please report the message */
  EXAO_CANCELLED = 6,        /* a batch's progress callback asked to stop (C++ API) */
  EXAO_CALLBACK_ERROR = 7    /* a callback the caller gave threw (C++ API) */
} exao_status;

/* A short English text for a status, e.g. "invalid argument"; "unknown status" for a value
 * outside the enum. Static storage, never NULL. */
EXAO_API const char* exao_status_string(exao_status status);

/* The library's version, "MAJOR.MINOR.PATCH". Static storage. */
EXAO_API const char* exao_version(void);

/* --- Options ------------------------------------------------------------------------------ */

/* RASTER serves only a camera's pixels (exao render, bench): engines refuse it (INVALID_ARGUMENT). */
typedef enum exao_backend {
  EXAO_BACKEND_BVH = 0, EXAO_BACKEND_BRUTE = 1, EXAO_BACKEND_EMBREE = 2, EXAO_BACKEND_RASTER = 3,
  EXAO_BACKEND_AUTO = 4  /* the default: masks, then Embree's rays; Embree's answer on every ray */
} exao_backend;
typedef enum exao_mask_mode { EXAO_MASKS_LUT = 0, EXAO_MASKS_EXACT = 1 } exao_mask_mode;
typedef enum exao_falloff { EXAO_FALLOFF_CONSTANT = 0, EXAO_FALLOFF_LINEAR = 1, EXAO_FALLOFF_QUADRATIC = 2 } exao_falloff;
typedef enum exao_sidedness { EXAO_SIDED_AUTO = 0, EXAO_SIDED_ONE = 1, EXAO_SIDED_TWO = 2 } exao_sidedness;
typedef enum exao_embree_rays {
  EXAO_EMBREE_SINGLE = 0, EXAO_EMBREE_PACKET4 = 1, EXAO_EMBREE_PACKET8 = 2, EXAO_EMBREE_PACKET16 = 3
} exao_embree_rays;

/* Engine settings; the meaning of each field is that of exao::api::Options. Always start from
 * exao_options_init, so that fields added later get their defaults. */
typedef struct exao_options {
  float radius;           /* r, world units, > 0 and at most 1e17; negative: 5% of the bounding-box
                             diagonal (default -1). 0 and NaN are refused, as in C++ */
  int samples;            /* N: a multiple of 32 in [32, 1024] (default 128) */
  exao_falloff falloff;   /* default EXAO_FALLOFF_CONSTANT */
  uint64_t pattern_seed;  /* default 0x65CA0 */
  exao_sidedness sidedness; /* default EXAO_SIDED_AUTO */
  exao_mask_mode mask_mode; /* default EXAO_MASKS_EXACT */
  float origin_offset;    /* eps, world units, >= 0; negative (default -1): the point's own scale,
                             max(1e-6, 1e-4 * max |p_k|), as in C++ (exao.hpp, Options) */
  int threads;            /* worker threads of batch queries, 0 to 256 (or 4x the cores); 0: one
                             per core (default 0) */
  exao_backend backend;   /* default EXAO_BACKEND_AUTO */
  int table_resolution;   /* look-up table cells per side, 0 (default for N) or [4, 256] */
  int bvh_branching;      /* 2 or 4 (default 4) */
  exao_embree_rays embree_rays; /* batch queries of the embree backend (default PACKET16) */
} exao_options;

/* Fills *options with the defaults. NULL is ignored. */
EXAO_API void exao_options_init(exao_options* options);

/* --- Meshes ------------------------------------------------------------------------------- */

/* The caller's triangle arrays, copied by exao_engine_create (free them any time after).
 * Triangle t is vertices indices[3t..3t+2] (from byte offset t * index_stride), or without
 * indices the vertices 3t, 3t+1, 3t+2. Front faces are counter-clockwise (glTF). */
typedef struct exao_mesh {
  const float* vertices;      /* vertex i: x, y, z at byte offset i * vertex_stride; 4-byte aligned */
  size_t vertex_count;
  size_t vertex_stride;       /* bytes, a multiple of 4, >= 12; 0 means 12 (tightly packed) */
  const uint32_t* indices;    /* NULL: a triangle soup; else each index < vertex_count */
  size_t index_stride;        /* bytes, a multiple of 4, >= 12; 0 means 12 */
  size_t triangle_count;
  const uint8_t* two_sided;   /* per triangle, 0: one-sided; NULL: every triangle two-sided */
  const float* transform;     /* NULL, or 12 floats: row-major 3x4 M, world = M * (x, y, z, 1) */
} exao_mesh;

/* --- Engines ------------------------------------------------------------------------------ */

typedef struct exao_engine exao_engine; /* opaque */

/* Builds an engine from `mesh_count` meshes (one scene). On success *engine is a new handle
 * (release it with exao_engine_destroy); on an error *engine is set to NULL and, when
 * error_buffer is not NULL, the message is written there (truncated to error_buffer_size - 1
 * bytes, NUL-terminated). options NULL means the defaults. Errors: EXAO_INVALID_ARGUMENT
 * (meshes or engine NULL, a bad stride or option, an index out of range, a non-finite vertex,
 * no triangle of non-zero area), EXAO_BACKEND_ERROR, EXAO_OUT_OF_MEMORY. */
EXAO_API exao_status exao_engine_create(const exao_mesh* meshes, size_t mesh_count, const exao_options* options,
                                        exao_engine** engine, char* error_buffer, size_t error_buffer_size);

/* Builds an engine from a built-in scene ("room", "plane-pair", "sphere-on-plane") or a scene
 * file (.gltf .glb .obj .ply .off .stl). Errors as exao_engine_create, plus EXAO_FILE_ERROR. */
EXAO_API exao_status exao_engine_open(const char* name_or_path, const exao_options* options, exao_engine** engine,
                                      char* error_buffer, size_t error_buffer_size);

/* Releases an engine. NULL is ignored. No query may be running on it. */
EXAO_API void exao_engine_destroy(exao_engine* engine);

/* An engine over the same scene with other settings (exao::api::Engine::with_settings): it
 * shares the scene's structures (nothing is rebuilt) and outlives `engine`; destroy it with
 * exao_engine_destroy. radius and origin_offset negative, samples 0: the engine's own. Errors:
 * EXAO_INVALID_ARGUMENT naming settings.radius, settings.origin_offset or settings.samples. */
EXAO_API exao_status exao_engine_with_settings(const exao_engine* engine, float radius, float origin_offset, int samples,
                                               exao_engine** derived, char* error_buffer, size_t error_buffer_size);

/* What an engine was built with, defaults resolved (see exao::api::EngineInfo). */
typedef struct exao_engine_info {
  exao_backend backend;
  exao_mask_mode mask_mode;
  exao_falloff falloff;
  int samples;                  /* N */
  size_t mask_words;            /* 64-bit words per mask: (N + 63) / 64 */
  float radius;                 /* r */
  float origin_offset;          /* eps, or the default's floor 1e-6 */
  int threads;
  size_t triangles;
  size_t two_sided_triangles;
  size_t zero_area_skipped;
  size_t beyond_limit_skipped;  /* triangles dropped for a vertex beyond +-1e17 */
  float bounds_lo[3];
  float bounds_hi[3];
  int table_resolution;
  size_t table_bytes;
  const char* simd;             /* the level the mask kernels run: "scalar", "sse2", "sse4", "avx2",
                                   "avx512"; "none" for the embree backend; static storage */
  float origin_offset_per_magnitude; /* 1e-4 with the default offset: eps(p) = max(origin_offset,
                                   this * max |p_k|); 0 when an offset was given */
} exao_engine_info;

/* Fills *info. Errors: EXAO_INVALID_ARGUMENT when engine or info is NULL. */
EXAO_API exao_status exao_engine_get_info(const exao_engine* engine, exao_engine_info* info);

/* N, the rays per receiver; 0 for a NULL engine. */
EXAO_API int exao_engine_samples(const exao_engine* engine);

/* Copies the message of the calling thread's most recent query into buffer, when that query was
 * on this engine and failed (like errno: per thread, so concurrent queries never see each
 * other's messages); "" when it succeeded, or was on another engine, or there was none. Truncated
 * to buffer_size - 1 bytes and NUL-terminated. Returns the message's full length in bytes (as
 * snprintf does), 0 for a NULL engine. buffer may be NULL when buffer_size is 0. */
EXAO_API size_t exao_engine_last_error(const exao_engine* engine, char* buffer, size_t buffer_size);

/* --- Queries ------------------------------------------------------------------------------ */

/* A receiver for batch queries: the same layout as exao::api::Receiver. */
typedef struct exao_receiver {
  float position[3]; /* world units, finite */
  float normal[3];   /* finite, need not be unit, squared length a normal float */
  uint64_t key;      /* picks the pattern's jitter: pixel, vertex or texel index, ... */
  uint32_t exclude;  /* 0: every triangle may block; k + 1: the triangles of object k (mesh k of
                        the build) block none of this receiver's rays, as C++'s
                        Receiver::excluded_object = k. Offset by one so that a zero-initialised
                        receiver excludes nothing. */
} exao_receiver;

/* AO in [0, 1] at one point, computed on the calling thread. Errors: EXAO_INVALID_ARGUMENT
 * (a NULL pointer, a non-finite position, a non-finite or too short normal). */
EXAO_API exao_status exao_ao(const exao_engine* engine, const float position[3], const float normal[3], uint64_t key,
                             float* ao);

/* The occlusion mask of one point: bit i of words (words[i / 64] >> (i % 64)) is set when ray i
 * is blocked; word_count must be at least (N + 63) / 64 (extra words are zeroed). When
 * directions is not NULL it receives 3 * N floats, ray i's world unit direction at 3i; when
 * lengths is not NULL, N floats, ray i's length (world units). When origin is not NULL it
 * receives the rays' common origin p' (3 floats). */
EXAO_API exao_status exao_mask(const exao_engine* engine, const float position[3], const float normal[3],
                               uint64_t key, uint64_t* words, size_t word_count, float* origin, float* directions,
                               float* lengths);

/* ao[i] = AO of receivers[i], i < count, in parallel on the engine's threads. count 0 is a
 * no-op. A bad receiver (non-finite position, a normal that cannot be normalised) gets
 * ao NaN while every other is computed; the call then returns EXAO_INVALID_ARGUMENT, and
 * exao_engine_last_error names the first bad receiver and how many there were. */
EXAO_API exao_status exao_ao_batch(const exao_engine* engine, const exao_receiver* receivers, size_t count, float* ao);

/* exao_ao_batch with one status per receiver: statuses[i] (count entries, not NULL) is EXAO_OK
 * for a receiver that was computed, EXAO_INVALID_ARGUMENT for a bad one (whose ao is NaN). */
EXAO_API exao_status exao_ao_batch_statuses(const exao_engine* engine, const exao_receiver* receivers, size_t count,
                                            float* ao, exao_status* statuses);

/* Masks of count receivers, in parallel: receiver i's (N + 63) / 64 words at
 * words[i * ((N + 63) / 64)]; `words` holds count * ((N + 63) / 64) words. */
EXAO_API exao_status exao_mask_batch(const exao_engine* engine, const exao_receiver* receivers, size_t count,
                                     uint64_t* words);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* EXAO_EXAO_H */
