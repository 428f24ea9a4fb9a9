/* A C99 program that knows exao only through its installed package (CMake or pkg-config). */
#include <stdio.h>

#include <exao/exao.h>

int main(void) {
  exao_options options;
  exao_options_init(&options);
  options.samples = 128;
  options.radius = 1.0f;
  options.origin_offset = 0.0f;
  exao_engine* engine = NULL;
  char message[256];
  if (exao_engine_open("plane-pair", &options, &engine, message, sizeof message) != EXAO_OK) {
    fprintf(stderr, "open: %s\n", message);
    return 1;
  }
  /* Floor at y = 0, ceiling at y = 0.5: AO = (h / r)^2 = 0.25 on average over keys. */
  const float p[3] = {0.0f, 0.0f, 0.0f}, n[3] = {0.0f, 1.0f, 0.0f};
  double sum = 0.0;
  for (uint64_t key = 0; key < 64; ++key) {
    float ao = -1.0f;
    if (exao_ao(engine, p, n, key, &ao) != EXAO_OK) return 1;
    sum += ao;
  }
  const float zero[3] = {0.0f, 0.0f, 0.0f};
  float ignored;
  const exao_status bad = exao_ao(engine, p, zero, 1, &ignored);
  exao_engine_last_error(engine, message, sizeof message);
  printf("exao %s: mean AO %.4f (expected 0.25); zero normal -> %s: %s\n", exao_version(), sum / 64.0,
         exao_status_string(bad), message);
  exao_engine_destroy(engine);
  return (sum / 64.0 > 0.23 && sum / 64.0 < 0.27 && bad == EXAO_INVALID_ARGUMENT) ? 0 : 1;
}
