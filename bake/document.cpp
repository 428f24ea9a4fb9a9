#include "bake/document.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "bake/document_impl.h"
#include "bake/gltf_access.h"
#include "bake/scene_to_gltf.h"
#include "core/cutouts.h"
#include "io/gltf_cutouts.h"
#include "io/gltf_file.h"
#include "core/ground_plane.h"
#include "io/load_scene.h"

namespace exao::bake {
namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// scene_to_gltf writes the triangles grouped by (material, two-sided) in key order and the walk
// reads them back in that order: the document's triangle k is scene triangle order[k]. The cut-outs
// follow (their own vertex floats decide, so the round trip through glTF changes no decision).
std::shared_ptr<const Cutouts> cutouts_in_document_order(const Scene& scene, std::size_t count) {
  if (!scene.cutouts) return nullptr;
  std::map<std::pair<std::int32_t, std::uint8_t>, std::vector<std::uint32_t>> groups;
  for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
    groups[{scene.material[t], scene.two_sided[t]}].push_back(static_cast<std::uint32_t>(t));
  }
  std::vector<std::uint32_t> order;
  for (const auto& [key, members] : groups) order.insert(order.end(), members.begin(), members.end());
  if (order.size() != count) return nullptr;
  auto out = std::make_shared<Cutouts>(*scene.cutouts);
  out->of_triangle.assign(count, -1);
  for (std::size_t k = 0; k < count; ++k) {
    if (order[k] < scene.cutouts->of_triangle.size()) out->of_triangle[k] = scene.cutouts->of_triangle[order[k]];
  }
  return out;
}

bool is_data_uri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

Result<std::unique_ptr<Document::Impl>> read_gltf(const std::string& path) {
  auto impl = std::make_unique<Document::Impl>();
  Result<gltf::File> file = gltf::read_file(path, &gltf::keep_image_bytes, &impl->image_bytes);  // kept encoded: save() copies them
  if (!file) return std::unexpected(file.error());
  impl->model = std::move(file->model);
  impl->image_bytes.resize(impl->model.images.size());
  impl->from_gltf = true;
  impl->source_path = path;
  impl->base_folder = std::filesystem::path(path).parent_path().string();
  impl->input_files.push_back(path);
  const std::filesystem::path folder(impl->base_folder);
  // The input's files as it was written: decoding merged its buffers into one, and the save
  // writes plain buffers.
  bool all_embedded = !file->binary && !file->buffer_uris.empty();
  for (const std::string& uri : file->buffer_uris) {
    if (!uri.empty() && !is_data_uri(uri)) {
      all_embedded = false;
      impl->input_files.push_back((folder / uri).string());
    }
  }
  impl->embedded_buffers = all_embedded;
  impl->notes.insert(impl->notes.end(), file->notes.begin(), file->notes.end());
  auto walk = walk_model(ModelBytes(impl->model));
  if (!walk) return std::unexpected(walk.error());
  impl->walk = std::move(*walk);
  impl->walk.scene.cutouts = gltf::read_cutouts(ModelBytes(impl->model), impl->walk, impl->image_bytes, impl->notes);
  for (std::size_t i = 0; i < impl->model.images.size(); ++i) {
    const tinygltf::Image& image = impl->model.images[i];
    if (image.uri.empty() || is_data_uri(image.uri)) continue;
    impl->input_files.push_back((folder / image.uri).string());
    if (impl->image_bytes[i].empty()) {
      impl->notes.push_back("image '" + image.uri + "' is missing beside the input: its reference is kept as it was");
    }
  }
  return impl;
}

}  // namespace

Document::Document(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Document::Document(Document&&) noexcept = default;
Document& Document::operator=(Document&&) noexcept = default;
Document::~Document() = default;

const Scene& Document::scene() const { return impl_->walk.scene; }
Scene& Document::scene() { return impl_->walk.scene; }
const std::string& Document::name() const { return impl_->name; }
bool Document::from_gltf() const { return impl_->from_gltf; }
const std::vector<std::string>& Document::input_files() const { return impl_->input_files; }
const std::vector<std::string>& Document::notes() const { return impl_->notes; }

Result<Document> Document::from_scene(const Scene& scene, const ConvertOptions& convert) {
  auto impl = std::make_unique<Impl>();
  Result<tinygltf::Model> model = scene_to_gltf(scene, convert);
  if (!model) return std::unexpected(model.error());
  impl->model = std::move(*model);
  auto walk = walk_model(ModelBytes(impl->model));
  if (!walk) return fail(scene.name + ": " + walk.error().message);
  impl->walk = std::move(*walk);
  impl->name = scene.name;
  impl->walk.scene.name = scene.name;
  impl->walk.scene.report = scene.report;  // what the original loader skipped
  impl->walk.scene.cutouts = cutouts_in_document_order(scene, impl->walk.scene.triangle_count());
  return Document(std::move(impl));
}

namespace {

Result<Document> with_ground(Result<Document> document, const ConvertOptions& convert) {
  if (!document || !convert.ground) return document;
  Result<float> height = add_ground_plane(document->scene(), convert.ground_height);
  if (!height) return fail(document->name() + ": " + height.error().message);
  char note[160];
  std::snprintf(note, sizeof note, "ground plane at y = %g%s: an occluder only (no receivers, not written out)",
                static_cast<double>(*height), convert.ground_height ? "" : " (just below the lowest point)");
  document->impl().notes.emplace_back(note);
  return document;
}

}  // namespace

Result<Document> Document::open(const std::string& name_or_path, const ConvertOptions& convert) {
  const std::string ext = lower_extension(name_or_path);
  const std::vector<std::string> builtins = builtin_scene_names();
  const bool builtin = std::find(builtins.begin(), builtins.end(), name_or_path) != builtins.end();
  if (builtin || (ext != ".gltf" && ext != ".glb")) {
    Result<Scene> scene = open_scene(name_or_path);
    if (!scene) return std::unexpected(scene.error());
    Result<Document> document = from_scene(*scene, convert);
    if (document && !builtin) document->impl_->input_files.push_back(name_or_path);
    return with_ground(std::move(document), convert);
  }
  Result<std::unique_ptr<Impl>> impl =
      gltf::read_guarded<std::unique_ptr<Impl>>(name_or_path, [&] { return read_gltf(name_or_path); });
  if (!impl) return std::unexpected(impl.error());
  (*impl)->name = std::filesystem::path(name_or_path).stem().string();
  (*impl)->walk.scene.name = (*impl)->name;
  return with_ground(Document(std::move(*impl)), convert);
}

}  // namespace exao::bake
