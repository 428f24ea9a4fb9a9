// exao bake: AO baked into a glTF model, per vertex (COLOR_0 or _AO) or per texel (an
// occlusionTexture map), plus a preview picture of the result.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include <fcntl.h>
#include <unistd.h>

#include "bake/bake.h"
#include "bake/document.h"
#include "bake/preview.h"
#include "bake/save.h"
#include "cli/backends.h"
#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/progress_bar.h"
#include "core/image_io.h"
#include "core/load_scene.h"

namespace exao::cli {
namespace {

struct BakeCommandOptions {
  SceneOptions scene;
  RayOptions rays;
  MethodOptions method;
  CameraOptions camera;
  std::string output;                  // default: <scene>.glb (built-in, OBJ...) or <stem>-ao.<ext>
  bool vertex = false;
  std::optional<int> texture;
  bool attribute = false;
  std::string normals = "geometric";
  int uv_set = 0;
  int texel_samples = 4;
  int margin = 4;
  int png_bits = 8;
  std::optional<std::string> preview;  // default: <output stem>-preview.png; "" for none
  std::string compare;                 // a second method, timed on the same receivers
};

namespace fs = std::filesystem;

std::string default_output(const BakeCommandOptions& options, const bake::Document& document) {
  if (!document.from_gltf()) return document.name() + ".glb";
  std::string ext = fs::path(options.scene.scene).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return document.name() + "-ao" + ext;
}

// The output folder is checked before the (long) bake rather than after it, by creating a file
// there: permission bits alone do not tell (root passes access(2) even where nothing can be
// created, as in /proc).
Result<void> check_folder(const std::string& path) {
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return fail(path + ": folder " + folder.string() + " does not exist");
  const std::string probe = (folder / (".exao-probe-" + std::to_string(::getpid()))).string();
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0) return fail(path + ": folder " + folder.string() + " is not writable");
  ::close(fd);
  ::unlink(probe.c_str());
  return {};
}

void print_notes(const std::string& name, const std::vector<std::string>& notes) {
  for (const std::string& note : notes) std::fprintf(stderr, "exao: %s: %s\n", name.c_str(), note.c_str());
}

struct Timed {
  double seconds = 0.0;
};

int run_bake(const BakeCommandOptions& options) {
  const auto threads = thread_limit(options.rays.threads);
  if (!threads) return report(threads.error());
  Result<Method> method = parse_method(options.method.method);
  if (!method) return report(method.error());
  std::optional<Method> compare;
  if (!options.compare.empty()) {
    Result<Method> parsed = parse_method(options.compare);
    if (!parsed) return report(Error{"--compare: unknown method '" + options.compare + "' (embree, brute or bvh)"});
    compare = *parsed;
  }
  Result<BackendOptions> backend_options = make_backend_options(options.method);
  if (!backend_options) return report(backend_options.error());
  if (options.vertex && options.texture) return report(Error{"--vertex and --texture: choose one"});
  if (options.normals != "geometric" && options.normals != "file") {
    return report(Error{"--normals: must be geometric or file, got '" + options.normals + "'"});
  }
  bake::BakeOptions bake_options;
  bake_options.target = options.texture ? bake::Target::Texture : bake::Target::Vertex;
  bake_options.channel = options.attribute ? bake::VertexChannel::Attribute : bake::VertexChannel::Color;
  bake_options.normals = options.normals == "file" ? bake::NormalSource::File : bake::NormalSource::Geometric;
  bake_options.texture_size = options.texture.value_or(1024);
  bake_options.uv_set = options.uv_set;
  bake_options.texel_samples = options.texel_samples;
  bake_options.margin = options.margin;
  if (options.attribute && options.texture) return report(Error{"--attribute: only for vertex bakes"});
  if (options.png_bits != 8 && options.png_bits != 16) {
    return report(Error{"--png-bits: must be 8 or 16, got " + std::to_string(options.png_bits)});
  }
  if (options.texture && (*options.texture < 16 || *options.texture > 16384)) {
    return report(Error{"--texture: the map size must be from 16 to 16384 texels, got " + std::to_string(*options.texture)});
  }
  if (options.margin < 0 || options.margin > 64) {
    return report(Error{"--margin: must be from 0 to 64 texels, got " + std::to_string(options.margin)});
  }

  // A mesh without UVs gets a box-projection atlas laid out for this map size.
  bake::ConvertOptions convert;
  if (options.texture) {
    convert.atlas_size = *options.texture;
    convert.atlas_padding = 2 * options.margin + 2;
  }
  Result<bake::Document> document = bake::Document::open(options.scene.scene, convert);
  if (!document) return report(document.error());
  const Scene& scene = document->scene();
  const LoadReport& r = scene.report;
  const std::string& name = options.scene.scene;
  if (r.zero_area_skipped) {
    std::fprintf(stderr, "exao: %s: skipped %zu zero-area triangles of %zu\n", name.c_str(), r.zero_area_skipped, r.triangles_read);
  }
  if (r.non_finite_skipped) {
    std::fprintf(stderr, "exao: %s: skipped %zu triangles with NaN or infinite vertices\n", name.c_str(), r.non_finite_skipped);
  }
  print_notes(name, r.notes);
  print_notes(name, document->notes());
  apply_sidedness(document->scene(), options.scene.sided == "one"   ? Sidedness::One
                                     : options.scene.sided == "two" ? Sidedness::Two
                                                                    : Sidedness::Auto);

  const std::string output = options.output.empty() ? default_output(options, *document) : options.output;
  if (auto ok = check_output(output, options.scene.scene); !ok) return report(ok.error());
  bake::SaveOptions save_options{output, options.png_bits};
  if (auto planned = bake::planned_outputs(*document, nullptr, save_options); !planned) return report(planned.error());
  if (auto ok = check_folder(output); !ok) return report(ok.error());
  const std::string preview = options.preview.value_or((fs::path(output).parent_path() / fs::path(output).stem()).string() +
                                                       "-preview.png");
  if (!preview.empty()) {
    if (auto ok = check_output(preview, options.scene.scene); !ok) return report(ok.error());
  }

  Result<ShadowRays> rays = make_rays(options.rays, scene);
  if (!rays) return report(rays.error());
  Result<Camera> camera = choose_camera(options.camera, scene);
  if (!camera) return report(camera.error());
  Result<int> height = image_height(options.camera, *camera);
  if (!height) return report(height.error());
  std::vector<Method> methods{*method};
  if (compare) methods.push_back(*compare);
  Result<Backends> backends = Backends::prepare(scene, methods, *backend_options);
  if (!backends) return report(backends.error());
  std::optional<lut::MaskEngine> engine;
  if (*method != Method::Embree || (compare && *compare != Method::Embree)) {
    Result<lut::MaskEngine> built = backends->engine(*rays, backend_options->masks);
    if (!built) return report(built.error());
    engine = std::move(*built);
  }
  const auto ao_of = [&](Method m, Timed& timed) {
    return [&, m](std::span<const Receiver> receivers, const ProgressCallback& progress) {
      const auto start = std::chrono::steady_clock::now();
      const MaskSet masks = backends->run(m, *rays, engine ? &*engine : nullptr, receivers, progress);
      timed.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::vector<float> ao(masks.size());
      for (std::size_t i = 0; i < masks.size(); ++i) ao[i] = masks.ao(i);
      return ao;
    };
  };

  Timed main_time;
  Result<bake::BakeResult> result;
  {
    ProgressBar bar("bake");
    result = bake::bake(*document, bake_options, ao_of(*method, main_time), bar.callback());
  }
  if (!result) return report(result.error());
  print_notes(name, result->notes);

  // Outputs first, so that bad output paths give one line; then what was measured.
  std::vector<std::string> save_notes;
  Result<std::vector<std::string>> written = bake::save(*document, *result, save_options, save_notes);
  if (!written) return report(written.error());
  print_notes(name, save_notes);
  if (!preview.empty()) {
    const AoImage image = bake::render_preview(*document, *result, backends->embree(), *camera, options.camera.width, *height);
    // Grey AO on a dark slate background, so that open (white) surfaces keep their outline.
    std::vector<std::uint8_t> rgb(3 * image.ao.size());
    for (std::size_t i = 0; i < image.ao.size(); ++i) {
      const auto grey = static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(image.ao[i], 0.0f, 1.0f)));
      const bool hit = image.coverage[i] > 0.0f;
      rgb[3 * i] = hit ? grey : 46;
      rgb[3 * i + 1] = hit ? grey : 52;
      rgb[3 * i + 2] = hit ? grey : 64;
    }
    if (auto ok = write_png_bytes(rgb, image.width, image.height, 3, preview); !ok) return report(ok.error());
    written->push_back(preview);
  }
  const double rays_cast = static_cast<double>(result->receivers.size()) * rays->count();
  const auto throughput = [&](Method m, double seconds) {
    std::printf("  %-6s %9.3f s  %8.1f Mrays/s  %10.0f receivers/s\n", method_name(m), seconds,
                seconds > 0.0 ? rays_cast / seconds * 1e-6 : 0.0,
                seconds > 0.0 ? static_cast<double>(result->receivers.size()) / seconds : 0.0);
  };
  std::string what;
  if (result->target == bake::Target::Vertex) {
    what = std::to_string(result->receivers.size()) + " vertex receivers";
    if (result->meshes_split > 0) what += ", " + std::to_string(result->meshes_split) + " meshes split per node";
  } else {
    std::size_t covered = 0;
    for (const bake::AoMap& map : result->maps) covered += map.covered_texels;
    what = std::to_string(result->receivers.size()) + " texel receivers, " + std::to_string(covered) + " texels in " +
           std::to_string(result->maps.size()) + " map(s) of " + std::to_string(bake_options.texture_size) + "^2, " +
           std::to_string(bake_options.texel_samples) + " samples/texel";
  }
  std::printf("%s: %zu triangles, %s, N=%d, r=%g\n", name.c_str(), scene.triangle_count(), what.c_str(), rays->count(),
              static_cast<double>(rays->radius));
  throughput(*method, main_time.seconds);
  if (compare) {
    Timed compare_time;
    const auto compare_ao = ao_of(*compare, compare_time);
    std::size_t identical = 0;
    double largest = 0.0, sum = 0.0;
    {
      ProgressBar bar(std::string("compare ") + method_name(*compare));
      const std::span<const Receiver> all(result->receivers);
      for (std::size_t begin = 0; begin < all.size(); begin += bake::kBatch) {
        const std::size_t count = std::min(bake::kBatch, all.size() - begin);
        const std::vector<float> other = compare_ao(all.subspan(begin, count), {});
        for (std::size_t i = 0; i < count; ++i) {
          const double d = std::abs(static_cast<double>(other[i]) - result->ao[begin + i]);
          identical += d == 0.0 ? 1 : 0;
          largest = std::max(largest, d);
          sum += d;
        }
      }
    }
    throughput(*compare, compare_time.seconds);
    const double n = static_cast<double>(std::max<std::size_t>(1, result->receivers.size()));
    std::printf("  %s vs %s: %.2f%% of receivers identical, mean |dAO| %.5f, max %.4f; %s is %.2fx the speed of %s\n",
                method_name(*method), method_name(*compare), 100.0 * static_cast<double>(identical) / n, sum / n, largest,
                method_name(*method), main_time.seconds > 0.0 ? compare_time.seconds / main_time.seconds : 0.0,
                method_name(*compare));
  }

  std::string files;
  for (const std::string& file : *written) files += (files.empty() ? "" : ", ") + file;
  std::printf("-> %s\n", files.c_str());
  return 0;
}

}  // namespace

Command add_bake_command(CLI::App& app) {
  auto options = std::make_shared<BakeCommandOptions>();
  CLI::App* command = app.add_subcommand("bake", "Bake AO into a glTF: per vertex (COLOR_0 or _AO) or an occlusionTexture map");
  add_scene_options(*command, options->scene);
  add_ray_options(*command, options->rays);
  add_method_options(*command, options->method);
  add_camera_options(*command, options->camera);
  command->add_option("-o,--output", options->output,
                      "OUT.gltf or OUT.glb (default: <scene>.glb for built-in and non-glTF scenes, <stem>-ao.<ext> for glTF)");
  command->add_flag("--vertex", options->vertex, "AO per vertex (the default when --texture is not given)");
  command->add_option("--texture", options->texture, "AO per texel into a SIZE x SIZE occlusionTexture map per material");
  command->add_flag("--attribute", options->attribute, "Vertex AO as a float _AO attribute instead of COLOR_0");
  command->add_option("--normals", options->normals,
                      "Receiver normals: geometric (area-weighted face normals) or file (the NORMAL attribute)")
      ->capture_default_str();
  command->add_option("--uv-set", options->uv_set, "Lay the maps out by TEXCOORD_K")->capture_default_str();
  command->add_option("--texel-samples", options->texel_samples, "Receivers per texel: a square number (1 = texel centre)")
      ->capture_default_str();
  command->add_option("--margin", options->margin, "Dilation around each UV chart, texels")->capture_default_str();
  command->add_option("--png-bits", options->png_bits, "AO map PNG depth: 8 or 16")->capture_default_str();
  command->add_option("--preview", options->preview,
                      "PNG picture of the baked AO from the camera options (default <output stem>-preview.png; '' for none)");
  command->add_option("--compare", options->compare,
                      "Also time this method (embree, brute, bvh) on the same receivers and report how the answers agree");
  return [options, command]() { return command->parsed() ? run_bake(*options) : -1; };
}

}  // namespace exao::cli
