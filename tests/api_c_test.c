/* The C API (include/exao/exao.h), compiled as C: the same bits as `exao query` for the same
 * points, keys, N, radius and mask mode; single, mask and batch queries agree; bad arguments
 * return the right status with a message.
 *
 * Usage: api_c_test EXAO_BINARY WORK_FOLDER. Prints "N passed, N failed"; exits non-zero on a
 * failure. */

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "exao/exao.h"

static int passed = 0;
static int failed = 0;

#define CHECK(condition, ...)                                   \
  do {                                                          \
    if (condition) {                                            \
      ++passed;                                                 \
    } else {                                                    \
      ++failed;                                                 \
      fprintf(stderr, "%s:%d: CHECK(%s) failed: ", __FILE__, __LINE__, #condition); \
      fprintf(stderr, __VA_ARGS__);                             \
      fprintf(stderr, "\n");                                    \
    }                                                           \
  } while (0)

/* A deterministic generator (xorshift64*), so every run uses the same points. */
static uint64_t state = 0x9E3779B97F4A7C15ull;
static uint64_t next_u64(void) {
  state ^= state >> 12;
  state ^= state << 25;
  state ^= state >> 27;
  return state * 0x2545F4914F6CDD1Dull;
}
static float next_float(float lo, float hi) { return lo + (hi - lo) * (float)(next_u64() >> 40) / 16777216.0f; }

enum { kPoints = 600 };

/* Receivers in and on the built-in room (x in [-5, 5], y in [0, 4], z in [-4, 4]): half on the
 * floor facing up, half anywhere inside with random normals. */
static void make_receivers(exao_receiver* receivers, size_t count) {
  for (size_t i = 0; i < count; ++i) {
    exao_receiver* r = &receivers[i];
    r->position[0] = next_float(-4.9f, 4.9f);
    r->position[2] = next_float(-3.9f, 3.9f);
    if (i % 2 == 0) {
      r->position[1] = 0.0f;
      r->normal[0] = 0.0f, r->normal[1] = 1.0f, r->normal[2] = 0.0f;
    } else {
      r->position[1] = next_float(0.1f, 3.9f);
      r->normal[0] = next_float(-1.0f, 1.0f), r->normal[1] = next_float(-1.0f, 1.0f), r->normal[2] = next_float(-1.0f, 1.0f);
      if (fabsf(r->normal[0]) + fabsf(r->normal[1]) + fabsf(r->normal[2]) < 0.1f) r->normal[1] = 1.0f;
    }
    r->key = (i % 3 == 0) ? next_u64() : (uint64_t)i;
  }
}

/* Runs `exao query room --points ... <arguments>` and reads its values into ao. */
static int exao_query(const char* binary, const char* folder, const exao_receiver* receivers, size_t count,
                      const char* arguments, float* ao) {
  char points[1024], output[1024], command[4096];
  snprintf(points, sizeof points, "%s/api_c_points.txt", folder);
  snprintf(output, sizeof output, "%s/api_c_ao.txt", folder);
  FILE* file = fopen(points, "w");
  if (!file) return 0;
  for (size_t i = 0; i < count; ++i) {
    const exao_receiver* r = &receivers[i];
    fprintf(file, "%.9g %.9g %.9g %.9g %.9g %.9g %llu\n", r->position[0], r->position[1], r->position[2], r->normal[0],
            r->normal[1], r->normal[2], (unsigned long long)r->key);
  }
  fclose(file);
  snprintf(command, sizeof command, "\"%s\" query room --points \"%s\" -o \"%s\" %s > /dev/null", binary, points, output,
           arguments);
  if (system(command) != 0) return 0;
  file = fopen(output, "r");
  if (!file) return 0;
  size_t n = 0;
  char line[64];
  while (n < count && fgets(line, sizeof line, file)) ao[n++] = strtof(line, NULL);
  fclose(file);
  remove(points);
  remove(output);
  return n == count;
}

static void same_as_exao_query(const char* binary, const char* folder, const exao_options* options,
                               const char* arguments) {
  static exao_receiver receivers[kPoints];
  static float expected[kPoints], batch[kPoints];
  static uint64_t words[kPoints * 16];
  make_receivers(receivers, kPoints);
  CHECK(exao_query(binary, folder, receivers, kPoints, arguments, expected), "exao query %s", arguments);

  exao_engine* engine = NULL;
  char message[256];
  const exao_status created = exao_engine_open("room", options, &engine, message, sizeof message);
  CHECK(created == EXAO_OK, "exao_engine_open: %s", message);
  if (created != EXAO_OK) return;
  exao_engine_info info;
  CHECK(exao_engine_get_info(engine, &info) == EXAO_OK, "info");
  const size_t per = info.mask_words;
  CHECK(per == (size_t)(info.samples + 63) / 64, "mask_words %zu", per);
  CHECK(exao_ao_batch(engine, receivers, kPoints, batch) == EXAO_OK, "exao_ao_batch");
  CHECK(exao_mask_batch(engine, receivers, kPoints, words) == EXAO_OK, "exao_mask_batch");
  int differing = 0;
  for (size_t i = 0; i < kPoints; ++i) {
    float single = -1.0f;
    uint64_t mask[17];
    const exao_status s = exao_ao(engine, receivers[i].position, receivers[i].normal, receivers[i].key, &single);
    const exao_status m = exao_mask(engine, receivers[i].position, receivers[i].normal, receivers[i].key, mask, 17,
                                    NULL, NULL, NULL);
    int blocked = 0, same_words = 1;
    for (size_t w = 0; w < per; ++w) {
      blocked += __builtin_popcountll(mask[w]);
      same_words &= mask[w] == words[i * per + w];
    }
    const float from_mask = 1.0f - (float)blocked / (float)info.samples;
    if (s != EXAO_OK || m != EXAO_OK || single != expected[i] || batch[i] != expected[i] || from_mask != expected[i] ||
        !same_words || mask[16] != 0) {
      if (++differing <= 5) {
        CHECK(0, "%s: receiver %zu: exao query %.9g, exao_ao %.9g, batch %.9g, mask %.9g, words %s", arguments, i,
              expected[i], single, batch[i], from_mask, same_words ? "same" : "differ");
      }
    }
  }
  CHECK(differing == 0, "%s: %d of %d receivers differ", arguments, differing, kPoints);
  exao_engine_destroy(engine);
}

static void rays_of_a_mask(void) {
  exao_options options;
  exao_options_init(&options);
  options.samples = 64;
  options.radius = 0.5f;
  options.mask_mode = EXAO_MASKS_EXACT; /* the look-up table may differ on rays near the ceiling */
  exao_engine* engine = NULL;
  CHECK(exao_engine_open("plane-pair", &options, &engine, NULL, 0) == EXAO_OK, "open plane-pair");
  if (!engine) return;
  const float p[3] = {0.0f, 0.0f, 0.0f}, n[3] = {0.0f, 1.0f, 0.0f};
  uint64_t words[1];
  float origin[3], directions[3 * 64], lengths[64];
  CHECK(exao_mask(engine, p, n, 5, words, 1, origin, directions, lengths) == EXAO_OK, "exao_mask with rays");
  int consistent = 1;
  for (int i = 0; i < 64; ++i) {
    const float* d = &directions[3 * i];
    const float reach = origin[1] + lengths[i] * d[1];
    const int blocked = (int)((words[0] >> i) & 1u);
    if (fabsf(reach - 0.5f) > 1e-4f && blocked != (reach > 0.5f)) consistent = 0;
    if (fabsf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - 1.0f) > 1e-5f || d[1] <= 0.0f) consistent = 0;
  }
  CHECK(consistent, "a ray is blocked iff it reaches the ceiling at y = 0.5");
  exao_engine_destroy(engine);
}

/* exao_receiver.exclude: 0 excludes nothing, k + 1 excludes mesh k, as C++'s excluded_object. A
 * point under a two-sided roof (mesh 0) over a floor (mesh 1) is half blocked by the roof unless
 * it excludes it, and the zero-initialised field excludes nothing. */
static void excluded_mesh(void) {
  const float roof[9] = {-50, 1, -50, 0, 1, 50, 50, 1, -50};
  const float floor_[9] = {-50, 0, -50, 50, 0, -50, 0, 0, 50};
  exao_mesh meshes[2] = {{roof, 3, 0, NULL, 0, 1, NULL, NULL}, {floor_, 3, 0, NULL, 0, 1, NULL, NULL}};
  exao_options options;
  exao_options_init(&options);
  options.samples = 64;
  options.radius = 4.0f;
  exao_engine* engine = NULL;
  char message[256] = "";
  CHECK(exao_engine_create(meshes, 2, &options, &engine, message, sizeof message) == EXAO_OK, "two meshes: %s", message);
  if (!engine) return;
  exao_receiver receivers[3] = {{{0, 0.001f, 0}, {0, 1, 0}, 5, 0}, {{0, 0.001f, 0}, {0, 1, 0}, 5, 1},
                                {{0, 0.001f, 0}, {0, 1, 0}, 5, 2}};
  float ao[3] = {-1, -1, -1};
  CHECK(exao_ao_batch(engine, receivers, 3, ao) == EXAO_OK, "batch with exclusions");
  CHECK(ao[0] < 0.5f, "the roof blocks: AO %g", (double)ao[0]);
  CHECK(ao[1] == 1.0f, "excluding mesh 0 (exclude 1) leaves nothing above: AO %g", (double)ao[1]);
  CHECK(ao[2] == ao[0], "excluding the floor under the point changes nothing: AO %g vs %g", (double)ao[2], (double)ao[0]);
  exao_engine_destroy(engine);
}

static void bad_arguments(void) {
  exao_options options;
  exao_options_init(&options);
  char message[256] = "unchanged";
  exao_engine* engine = (exao_engine*)&options; /* must be reset to NULL on failure */

  options.samples = 0;
  CHECK(exao_engine_open("room", &options, &engine, message, sizeof message) == EXAO_INVALID_ARGUMENT, "samples 0");
  CHECK(engine == NULL, "engine reset");
  CHECK(strstr(message, "samples") != NULL, "message names samples: %s", message);
  options.samples = 64;
  options.radius = 0.0f; /* refused, as C++ refuses it: negative is the C spelling of "the default" */
  CHECK(exao_engine_open("room", &options, &engine, message, sizeof message) == EXAO_INVALID_ARGUMENT, "radius 0");
  CHECK(strstr(message, "options.radius") != NULL, "message names options.radius: %s", message);
  options.radius = NAN;
  CHECK(exao_engine_open("room", &options, &engine, message, 8) == EXAO_INVALID_ARGUMENT, "radius NaN");
  CHECK(strlen(message) == 7, "message truncated to the buffer: '%s'", message);
  options.radius = -1.0f;
  CHECK(exao_engine_open("/nonexistent.glb", &options, &engine, message, sizeof message) == EXAO_FILE_ERROR, "missing file");
  CHECK(strstr(message, "/nonexistent.glb") != NULL, "message names the file: %s", message);
  CHECK(exao_engine_open(NULL, &options, &engine, message, sizeof message) == EXAO_INVALID_ARGUMENT, "null name");
  CHECK(exao_engine_open("room", &options, NULL, NULL, 0) == EXAO_INVALID_ARGUMENT, "null out");
  CHECK(exao_engine_create(NULL, 1, &options, &engine, NULL, 0) == EXAO_INVALID_ARGUMENT, "null meshes");

  const float vertices[9] = {-1, 1, -1, 1, 1, -1, 0, 1, 1};
  const uint32_t bad_indices[3] = {0, 1, 9};
  exao_mesh mesh = {vertices, 3, 0, bad_indices, 0, 1, NULL, NULL};
  CHECK(exao_engine_create(&mesh, 1, &options, &engine, message, sizeof message) == EXAO_INVALID_ARGUMENT, "index 9");
  CHECK(strstr(message, "vertex 9") != NULL, "message names the index: %s", message);
  mesh.indices = NULL;
  options.radius = 2.0f;
  CHECK(exao_engine_create(&mesh, 1, &options, &engine, message, sizeof message) == EXAO_OK, "good mesh: %s", message);
  if (!engine) return;

  const float p[3] = {0, 0, 0}, up[3] = {0, 1, 0}, zero[3] = {0, 0, 0}, nan_p[3] = {NAN, 0, 0};
  float ao = -1.0f;
  CHECK(exao_ao(NULL, p, up, 1, &ao) == EXAO_INVALID_ARGUMENT, "null engine");
  CHECK(exao_ao(engine, NULL, up, 1, &ao) == EXAO_INVALID_ARGUMENT, "null position");
  CHECK(exao_ao(engine, p, up, 1, NULL) == EXAO_INVALID_ARGUMENT, "null ao");
  CHECK(exao_ao(engine, nan_p, up, 1, &ao) == EXAO_INVALID_ARGUMENT, "NaN position");
  CHECK(exao_engine_last_error(engine, message, sizeof message) > 0 && strstr(message, "position") != NULL,
        "last error names the position: %s", message);
  CHECK(exao_ao(engine, p, zero, 1, &ao) == EXAO_INVALID_ARGUMENT, "zero normal");
  CHECK(strstr((exao_engine_last_error(engine, message, sizeof message), message), "normal") != NULL, "names normal: %s", message);
  CHECK(ao == -1.0f, "ao untouched on errors");
  uint64_t words[1];
  CHECK(exao_mask(engine, p, up, 1, words, 0, NULL, NULL, NULL) == EXAO_INVALID_ARGUMENT, "word_count 0");
  exao_receiver receivers[2] = {{{0, 0, 0}, {0, 1, 0}, 0, 0}, {{0, 0, 0}, {0, 0, 0}, 1, 0}};
  float out[2] = {-1.0f, -1.0f};
  CHECK(exao_ao_batch(engine, receivers, 2, out) == EXAO_INVALID_ARGUMENT, "bad receiver in a batch");
  exao_engine_last_error(engine, message, sizeof message);
  CHECK(strstr(message, "receivers[1]") != NULL, "names receivers[1]: %s", message);
  CHECK(out[0] > 0.0f && out[0] < 1.0f && isnan(out[1]), "the good receiver computed, the bad one NaN: %g %g", out[0], out[1]);
  CHECK(exao_ao_batch(engine, NULL, 2, out) == EXAO_INVALID_ARGUMENT, "null receivers");
  CHECK(exao_ao_batch(engine, receivers, 1, out) == EXAO_OK && out[0] > 0.0f && out[0] < 1.0f, "good batch %g", out[0]);
  CHECK(exao_engine_last_error(engine, message, sizeof message) == 0 && message[0] == '\0',
        "a query that succeeds clears the message: '%s'", message);
  CHECK(exao_ao(engine, p, up, 0, &ao) == EXAO_OK && ao == out[0], "single == batch (same point, normal and key)");
  CHECK(exao_engine_last_error(NULL, NULL, 0) == 0, "null engine, no message");

  /* Per-receiver statuses: the bad receiver is named and NaN, the good one computed. */
  exao_status statuses[2] = {EXAO_INTERNAL_ERROR, EXAO_INTERNAL_ERROR};
  out[0] = out[1] = -1.0f;
  CHECK(exao_ao_batch_statuses(engine, receivers, 2, out, statuses) == EXAO_INVALID_ARGUMENT, "one bad receiver");
  CHECK(statuses[0] == EXAO_OK && statuses[1] == EXAO_INVALID_ARGUMENT, "statuses %d %d", statuses[0], statuses[1]);
  CHECK(out[0] == ao && isnan(out[1]), "computed %g and NaN %g", out[0], out[1]);

  /* A derived engine with another radius and N equals one built with them. */
  exao_engine* derived = NULL;
  CHECK(exao_engine_with_settings(engine, 0.75f, -1.0f, 64, &derived, message, sizeof message) == EXAO_OK, "derived: %s",
        message);
  exao_engine* fresh = NULL;
  options.radius = 0.75f;
  options.samples = 64;
  CHECK(exao_engine_create(&mesh, 1, &options, &fresh, message, sizeof message) == EXAO_OK, "fresh: %s", message);
  if (derived && fresh) {
    float a = -1.0f, b = -2.0f;
    CHECK(exao_ao(derived, p, up, 5, &a) == EXAO_OK && exao_ao(fresh, p, up, 5, &b) == EXAO_OK && a == b,
          "derived == fresh: %g %g", a, b);
    CHECK(exao_engine_samples(derived) == 64, "derived N");
  }
  exao_engine_destroy(fresh);
  exao_engine_destroy(derived);
  derived = NULL;
  CHECK(exao_engine_with_settings(engine, 0.0f, -1.0f, 0, &derived, message, sizeof message) == EXAO_INVALID_ARGUMENT &&
            derived == NULL && strstr(message, "settings.radius") != NULL,
        "derived radius 0 refused: %s", message);
  exao_engine_destroy(engine);
  exao_engine_destroy(NULL);

  CHECK(strcmp(exao_status_string(EXAO_OK), "ok") == 0, "status text");
  CHECK(strcmp(exao_status_string(EXAO_FILE_ERROR), "file error") == 0, "status text");
  CHECK(strcmp(exao_status_string((exao_status)42), "unknown status") == 0, "status text");
  CHECK(exao_version()[0] != '\0', "version");
  exao_options_init(NULL);
}

int main(int argc, char** argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: api_c_test EXAO_BINARY WORK_FOLDER\n");
    return 2;
  }
  exao_options options;
  exao_options_init(&options);
  options.samples = 128;
  options.radius = 0.8f;
  /* The API's default offset follows each point, exao query's the diagonal: give one to both. */
  options.origin_offset = 0.001f;
  if (options.backend != EXAO_BACKEND_AUTO) {
    fprintf(stderr, "FAIL: the default backend is %d, not EXAO_BACKEND_AUTO\n", (int)options.backend);
    return 1;
  }
  same_as_exao_query(argv[1], argv[2], &options, "-n 128 -r 0.8 --offset 0.001");
  options.backend = EXAO_BACKEND_BVH;
  options.mask_mode = EXAO_MASKS_LUT;
  same_as_exao_query(argv[1], argv[2], &options, "-n 128 -r 0.8 --offset 0.001 --masks lut --method bvh");
  options.samples = 1024;
  options.mask_mode = EXAO_MASKS_EXACT;
  options.radius = -1.0f; /* the default: 5% of the diagonal */
  same_as_exao_query(argv[1], argv[2], &options, "-n 1024 --offset 0.001 --masks exact --method bvh");
  options.samples = 64;
  options.radius = 0.4f;
  options.origin_offset = 0.01f;
  options.backend = EXAO_BACKEND_EMBREE;
  same_as_exao_query(argv[1], argv[2], &options, "-n 64 -r 0.4 --offset 0.01 --method embree");
  rays_of_a_mask();
  excluded_mesh();
  bad_arguments();
  printf("%d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
