// exao bake: AO baked into a glTF model, per vertex (COLOR_0 or _AO) or per texel (an
// occlusionTexture map), plus a preview picture of the result.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "bake/bake.h"
#include "bake/document.h"
#include "bake/preview.h"
#include "bake/save.h"
#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/progress_bar.h"
#include "core/agreement.h"
#include "core/grazing.h"
#include "io/image_io.h"
#include "io/load_scene.h"
#include "engine/engine.h"

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
  std::string uv = "auto";
  bool ground = false;                 // --ground given
  std::string ground_value;            // "", "auto" or a height along +Y
  int texel_samples = 4;
  int margin = 4;
  int png_bits = 8;
  std::optional<std::string> preview;  // default: <output stem>-preview.png; "" for none
  std::string compare;                 // a second method, timed on the same receivers
  ShardCliOptions shard;
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

// For `exao bake --compare M`: errors about the second engine's method name --compare.
const FlagOverrides kCompareFlags{{"method", "--compare"}};

// What the flags ask for, checked before any work: the engines' options (the second one for
// --compare) and the bake's.
struct BakePlan {
  engine::Options engine;
  std::optional<engine::Options> compare;
  bake::BakeOptions bake;
  bake::ConvertOptions convert;  // how the document is opened
};

Result<BakePlan> plan_bake(const BakeCommandOptions& options, FlagOverrides& flags) {
  BakePlan plan;
  Result<engine::Options> engine_options = make_options(options.scene, options.rays, options.method);
  if (!engine_options) return std::unexpected(engine_options.error());
  plan.engine = *engine_options;
  if (auto ok = engine::check_serves(plan.engine, engine::Receivers::Points); !ok) return std::unexpected(ok.error());
  if (!options.compare.empty()) {
    flags = kCompareFlags;
    Result<engine::Method> method = engine::parse_method(options.compare);
    if (!method) return std::unexpected(method.error());
    plan.compare = plan.engine;
    plan.compare->method = *method;
    if (auto ok = engine::check_serves(*plan.compare, engine::Receivers::Points); !ok) return std::unexpected(ok.error());
    flags.clear();
  }
  if (options.vertex && options.texture) return fail("--vertex and --texture: choose one");
  if (options.attribute && options.texture) return fail("--attribute: only for vertex bakes");
  if (options.normals != "geometric" && options.normals != "file") {
    return fail("normals: must be geometric or file, got '" + options.normals + "'");
  }
  bake::BakeOptions& b = plan.bake;
  b.target = options.texture ? bake::Target::Texture : bake::Target::Vertex;
  b.channel = options.attribute ? bake::VertexChannel::Attribute : bake::VertexChannel::Color;
  b.normals = options.normals == "file" ? bake::NormalSource::File : bake::NormalSource::Geometric;
  b.texture_size = options.texture.value_or(1024);
  b.uv_set = options.uv_set;
  if (options.uv != "auto" && options.uv != "file" && options.uv != "generate") {
    return fail("--uv: must be auto, file or generate, got '" + options.uv + "'");
  }
  b.uv = options.uv == "file" ? bake::UvMode::File : options.uv == "generate" ? bake::UvMode::Generate : bake::UvMode::Auto;
  b.texel_samples = options.texel_samples;
  b.margin = options.margin;
  // Before the document is opened: the map size and margin lay out its atlas.
  if (auto ok = bake::check_options(b); !ok) return std::unexpected(ok.error());
  // A mesh without UVs gets a box-projection atlas laid out for this map size.
  if (options.texture) {
    plan.convert.atlas_size = *options.texture;
    plan.convert.atlas_padding = 2 * options.margin + 2;
  }
  plan.convert.ground = options.ground;
  if (options.ground && !options.ground_value.empty() && options.ground_value != "auto") {
    std::size_t used = 0;
    float y = 0.0f;
    try {
      y = std::stof(options.ground_value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != options.ground_value.size() || !std::isfinite(y)) {
      return fail("--ground: must be auto or a height along +Y, got '" + options.ground_value + "'");
    }
    plan.convert.ground_height = y;
  }
  return plan;
}

// The document to bake: a glTF read whole, or anything else converted (a mesh without UVs gets a
// box-projection atlas laid out for the map size; --ground adds its plane). Its notes go to stderr.
Result<bake::Document> open_document(const BakeCommandOptions& options, const BakePlan& plan) {
  Result<bake::Document> document = bake::Document::open(options.scene.scene, plan.convert);
  if (!document) return document;
  print_load_report(options.scene.scene, document->scene().report);
  print_notes(options.scene.scene, document->notes());
  return document;
}

struct OutputPaths {
  bake::SaveOptions save;
  std::string preview;  // empty: none
  View view;            // of the preview
};

// Where the outputs go, checked before the (long) bake: never the input, a writable folder.
Result<OutputPaths> plan_outputs(const BakeCommandOptions& options, const bake::Document& document) {
  OutputPaths out;
  const std::string output = options.output.empty() ? default_output(options, document) : options.output;
  if (auto ok = check_output(output, options.scene.scene); !ok) return std::unexpected(ok.error());
  out.save = bake::SaveOptions{output, options.png_bits};
  if (auto planned = bake::planned_outputs(document, nullptr, out.save); !planned) return std::unexpected(planned.error());
  if (auto ok = check_folder(output); !ok) return std::unexpected(ok.error());
  out.preview = options.preview.value_or((fs::path(output).parent_path() / fs::path(output).stem()).string() + "-preview.png");
  if (out.preview.empty()) return out;
  if (auto ok = check_output(out.preview, options.scene.scene); !ok) return std::unexpected(ok.error());
  Result<View> view = choose_view(options.camera, document.scene());
  if (!view) return std::unexpected(view.error());
  out.view = *view;
  return out;
}

// The preview picture: grey AO on a dark slate background, so that open (white) surfaces keep
// their outline.
Result<void> write_preview(const OutputPaths& outputs, const bake::Document& document, const bake::BakeResult& result,
                           const engine::Engine& engine) {
  const AoImage image =
      bake::render_preview(document, result, *engine.geometry().embree(), outputs.view.camera, outputs.view.width,
                           outputs.view.height);
  std::vector<std::uint8_t> rgb(3 * image.ao.size());
  for (std::size_t i = 0; i < image.ao.size(); ++i) {
    const auto grey = static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(image.ao[i], 0.0f, 1.0f)));
    const bool hit = image.coverage[i] > 0.0f;
    rgb[3 * i] = hit ? grey : 46;
    rgb[3 * i + 1] = hit ? grey : 52;
    rgb[3 * i + 2] = hit ? grey : 64;
  }
  return write_png_bytes(rgb, image.width, image.height, 3, outputs.preview);
}

void print_throughput(engine::Method method, double seconds, std::size_t receivers, int samples) {
  const double rays = static_cast<double>(receivers) * samples;
  std::printf("  %-6s %9.3f s  %8.1f Mrays/s  %10.0f receivers/s\n", engine::method_name(method), seconds,
              seconds > 0.0 ? rays / seconds * 1e-6 : 0.0, seconds > 0.0 ? static_cast<double>(receivers) / seconds : 0.0);
}

// `merged`: what the counts came from (exao merge, --resume), in place of a throughput that
// would time no rays.
void print_summary(const std::string& name, const bake::Document& document, const bake::BakeOptions& bake_options,
                   const bake::BakeResult& result, const engine::Engine& engine, const std::string& merged) {
  std::string what;
  if (result.target == bake::Target::Vertex) {
    what = std::to_string(result.receivers.size()) + " vertex receivers";
    if (result.meshes_split > 0) what += ", " + std::to_string(result.meshes_split) + " meshes split per node";
  } else {
    std::size_t covered = 0;
    for (const bake::AoMap& map : result.maps) covered += map.covered_texels;
    what = std::to_string(result.receivers.size()) + " texel receivers, " + std::to_string(covered) + " texels in " +
           std::to_string(result.maps.size()) + " map(s) of " + std::to_string(bake_options.texture_size) + "^2, " +
           std::to_string(bake_options.texel_samples) + " samples/texel";
  }
  std::printf("%s: %zu triangles, %s, N=%d, r=%g\n", name.c_str(), document.scene().triangle_count(), what.c_str(),
              engine.samples(), static_cast<double>(engine.radius()));
  if (merged.empty()) {
    print_throughput(engine.method(), result.ao_seconds, result.receivers.size(), engine.samples());
  } else {
    std::printf("  AO from %s\n", merged.c_str());
  }
}

// The figures of DESIGN.md section 8, test 3, for the bake's own receivers.
void print_agreement(const char* mine, const char* reference, const Agreement& a) {
  std::printf("  %s vs %s: rays agree %.4f%% (%zu of %zu differ", mine, reference, 100.0 * a.ray_share(), a.rays_differ,
              a.rays);
  if (a.classified) std::printf(", %zu of them grazing an edge or a plane", a.rays_differ_grazing);
  std::printf("); identical AO on %.4f%% of %zu receivers", 100.0 * a.identical_share(), a.receivers);
  if (a.classified) {
    std::printf(" (%zu receivers differ only by grazing rays, %zu by a ray that does not graze)", a.receivers_grazing, a.ao_differ_not_grazing);
  }
  std::printf("; mean |dAO| %.5f, max %.4f\n", a.ao.sum_abs / double(std::max<std::size_t>(1, a.receivers)), a.ao.max_abs);
}

// --compare: the second engine on the same receivers, and how its answers agree with the bake's
// ray by ray. Chunk by chunk, the bake's engine runs once more (untimed), so that no mask set
// larger than a chunk is kept. With exact masks the rays that differ are sorted into grazing or
// not (core/grazing.h); table masks differ on too many rays to classify them all.
Result<void> run_compare(const Scene& scene, const bake::BakeResult& result, const engine::Engine& main,
                         const engine::Engine& other) {
  const bool classify = main.options().masks == lut::MaskMode::Exact ||
                        (main.method() == engine::Method::Embree && other.method() == engine::Method::Embree);
  std::optional<GrazingTest> grazing;
  if (classify) grazing.emplace(scene, main.rays());
  Agreement agreement;
  double seconds = 0.0;
  {
    ProgressBar bar(std::string("compare ") + engine::method_name(other.method()));
    const ProgressCallback progress = bar.callback();
    const std::span<const Receiver> all(result.receivers);
    for (std::size_t begin = 0; begin < all.size(); begin += engine::kChunk) {
      const std::span<const Receiver> chunk = all.subspan(begin, std::min(engine::kChunk, all.size() - begin));
      const auto start = std::chrono::steady_clock::now();
      Result<MaskSet> reference = other.masks(chunk);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (!reference) return std::unexpected(reference.error());
      Result<MaskSet> mine = main.masks(chunk);
      if (!mine) return std::unexpected(mine.error());
      agreement += compare_masks(*reference, *mine, chunk, main.rays(), grazing ? &*grazing : nullptr);
      if (progress) progress(begin + chunk.size(), all.size());
    }
  }
  print_throughput(other.method(), seconds, result.receivers.size(), other.samples());
  const char* a = engine::method_name(main.method());
  const char* b = engine::method_name(other.method());
  print_agreement(a, b, agreement);
  std::printf("  %s is %.2fx the speed of %s\n", a, result.ao_seconds > 0.0 ? seconds / result.ao_seconds : 0.0, b);
  return {};
}

// One geometry for the bake's engine, the --compare engine and the preview's primary rays.
Result<std::shared_ptr<const engine::Geometry>> bake_geometry(const BakePlan& plan, const OutputPaths& outputs,
                                                              const bake::Document& document) {
  std::vector<engine::Method> methods{plan.engine.method};
  if (plan.compare) methods.push_back(plan.compare->method);
  engine::GeometryOptions geometry_options;
  geometry_options.sidedness = plan.engine.sidedness;
  geometry_options.cutouts = plan.engine.cutouts;
  geometry_options.bvh = plan.engine.bvh;
  geometry_options.embree = !outputs.preview.empty();
  geometry_options.threads = plan.engine.threads;
  return engine::Geometry::build(document.scene(), methods, geometry_options);
}

// The bake's outputs first, so that bad output paths give one line; then what was measured
// (the summary, --compare's run) and the files written. The command's exit status.
int save_and_report(const BakeCommandOptions& options, const Invocation& invocation, const BakePlan& plan,
                    const OutputPaths& outputs, bake::Document& document, const bake::BakeResult& result,
                    const engine::Engine& engine, const std::optional<engine::Engine>& other) {
  const std::string& name = options.scene.scene;
  std::vector<std::string> save_notes;
  Result<std::vector<std::string>> written = bake::save(document, result, outputs.save, save_notes);
  if (!written) return report(written.error());
  print_notes(name, save_notes);
  if (!outputs.preview.empty()) {
    if (auto ok = write_preview(outputs, document, result, engine); !ok) return report(ok.error());
    written->push_back(outputs.preview);
  }
  print_summary(name, document, plan.bake, result, engine,
                invocation.merge ? invocation.merge->parts
                                 : options.shard.resume.empty() ? std::string() : "the chunks in " + options.shard.resume);
  if (other) {
    if (auto ok = run_compare(document.scene(), result, engine, *other); !ok) return report(ok.error(), kCompareFlags);
  }
  std::string files;
  for (const std::string& file : *written) files += (files.empty() ? "" : ", ") + file;
  std::printf("-> %s\n", files.c_str());
  return 0;
}

int run_bake(const BakeCommandOptions& given, const Invocation& invocation) {
  BakeCommandOptions options = given;
  if (invocation.merge && !invocation.merge->output.empty()) options.output = invocation.merge->output;
  FlagOverrides flags;
  Result<BakePlan> plan = plan_bake(options, flags);
  if (!plan) return report(plan.error(), flags);
  Result<std::optional<engine::Shard>> shard = resolve_shard(options.shard);
  if (!shard) return report(shard.error());
  if ((*shard || !options.shard.resume.empty()) && plan->compare) {
    return report(Error{"--compare: not with --shard or --resume (it times one whole run)"});
  }
  Result<bake::Document> document = open_document(options, *plan);
  if (!document) return report(document.error());
  Result<OutputPaths> outputs = plan_outputs(options, *document);
  if (!outputs) return report(outputs.error());
  // Sharded, resumed and merged bakes need the receivers before the bake proper: the same ones
  // bake() computes AO at, in its order (bake::bake_receivers leaves the document as it was).
  std::vector<Receiver> receivers;
  if (*shard || !options.shard.resume.empty() || invocation.merge) {
    Result<std::vector<Receiver>> found = bake::bake_receivers(*document, plan->bake);
    if (!found) return report(found.error());
    receivers = std::move(*found);
  }
  if (invocation.merge) {
    if (auto ok = check_merge_receivers(*invocation.merge, receivers); !ok) return report(ok.error());
  }

  auto geometry = bake_geometry(*plan, *outputs, *document);
  if (!geometry) return report(geometry.error());
  Result<engine::Engine> engine = engine::Engine::build(*geometry, plan->engine, engine::Receivers::Points);
  if (!engine) return report(engine.error());
  print_option_notes(*engine);
  std::optional<engine::Engine> other;
  if (plan->compare) {
    Result<engine::Engine> built = engine::Engine::build(*geometry, *plan->compare, engine::Receivers::Points);
    if (!built) return report(built.error(), kCompareFlags);
    other = std::move(*built);
  }

  // The shard's part, beside the output and never under its name; nothing else is written.
  const auto record = [&] {
    return make_record("bake", invocation, {options.scene.scene}, outputs->save.path, receivers, engine->samples());
  };
  if (*shard) return run_shard(record(), *engine, receivers, **shard);
  std::vector<std::uint32_t> resumed;
  if (!options.shard.resume.empty()) {
    Result<std::vector<std::uint32_t>> counts = run_resumable(options.shard.resume, record(), *engine, receivers);
    if (!counts) return report(counts.error());
    resumed = std::move(*counts);
  }

  Result<bake::BakeResult> result;
  {
    ProgressBar bar("bake");
    engine::RunOptions run;
    run.progress = bar.callback();
    if (invocation.merge) run.supplied_blocked = invocation.merge->blocked;
    if (!options.shard.resume.empty()) run.supplied_blocked = resumed;
    result = bake::bake(*document, plan->bake, *engine, run);
  }
  if (!result) return report(result.error());
  print_notes(options.scene.scene, result->notes);
  return save_and_report(options, invocation, *plan, *outputs, *document, *result, *engine, other);
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
  command->add_option("--uv", options->uv,
                      "Texture bakes: UVs from the file's set (file), a chart atlas made for the bake (generate), or the "
                      "file's set where it can hold AO and generated ones where not (auto)")
      ->capture_default_str();
  command->add_option("--ground", options->ground_value,
                      "Add an occluding ground plane (never written out) just below the model's lowest point (auto) or at height Y "
                      "along +Y")
      ->expected(0, 1);
  command->add_option("--texel-samples", options->texel_samples, "Receivers per texel: a square number (1 = texel centre)")
      ->capture_default_str();
  command->add_option("--margin", options->margin, "Dilation around each UV chart, texels")->capture_default_str();
  command->add_option("--png-bits", options->png_bits, "AO map PNG depth: 8 or 16")->capture_default_str();
  command->add_option("--preview", options->preview,
                      "PNG picture of the baked AO from the camera options (default <output stem>-preview.png; '' for none)");
  command->add_option("--compare", options->compare,
                      "Also time this method (embree, brute or bvh: raster serves only a camera's pixels) on the same receivers and report how the answers agree, ray by ray");
  add_shard_options(*command, options->shard, true);
  return [options, command](const Invocation& invocation) {
    options->ground = command->count("--ground") > 0;
    return command->parsed() ? run_bake(*options, invocation) : -1;
  };
}

}  // namespace exao::cli
