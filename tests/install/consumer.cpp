// A C++20 program that knows exao only through its installed package.
#include <cstdio>
#include <thread>
#include <vector>

#include <exao/exao.hpp>

int main() {
  namespace ao = exao::api;
  // A one-sided 2 x 2 quad facing down, 0.25 above the origin (indexed, in the caller's arrays).
  const float vertices[] = {-1, 0.25f, -1, 1, 0.25f, -1, 1, 0.25f, 1, -1, 0.25f, 1};
  const std::uint32_t indices[] = {0, 1, 2, 0, 2, 3};
  ao::Mesh mesh;
  mesh.vertices = vertices;
  mesh.vertex_count = 4;
  mesh.indices = indices;
  mesh.triangle_count = 2;
  ao::Options options;
  options.radius = 0.5f;
  options.samples = 256;
  options.origin_offset = 0.0f;
  ao::Result<ao::Engine> engine = ao::Engine::build(mesh, options);
  if (!engine) {
    std::fprintf(stderr, "build: %s\n", engine.error().message.c_str());
    return 1;
  }
  // Several threads query the same engine; the mean AO under the quad is (h / r)^2 = 0.25.
  std::vector<double> sums(4, 0.0);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < sums.size(); ++t) {
    threads.emplace_back([&, t] {
      for (std::uint64_t k = 0; k < 16; ++k) sums[t] += engine->ao({0, 0, 0}, {0, 1, 0}, 16 * t + k).value_or(-100.0f);
    });
  }
  for (std::thread& thread : threads) thread.join();
  const double mean = (sums[0] + sums[1] + sums[2] + sums[3]) / 64.0;
  const ao::Result<float> bad = engine->ao({0, 0, 0}, {0, 0, 0}, 1);
  const bool ok = mean > 0.23 && mean < 0.27 && !bad && bad.code() == ao::StatusCode::InvalidArgument;
  std::printf("exao %s: mean AO %.4f (expected 0.25), zero normal -> %s: %s\n", ao::version(), mean,
              ao::status_text(bad.code()), bad ? "" : bad.error().message.c_str());
  return ok ? 0 : 1;
}
