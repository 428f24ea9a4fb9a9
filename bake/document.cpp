#include "bake/document.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>

#include "bake/document_impl.h"
#include "bake/gltf_access.h"
#include "bake/scene_to_gltf.h"
#include "core/gltf_guard.h"
#include "core/load_scene.h"

namespace exao::bake {
namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Keeps every image's encoded bytes (AO needs no pixels): save() copies or embeds them as they were.
bool keep_image_bytes(tinygltf::Image*, const int index, std::string*, std::string*, int, int, const unsigned char* bytes,
                      int size, void* user) {
  auto& images = *static_cast<std::vector<std::vector<std::uint8_t>>*>(user);
  if (index < 0) return true;
  if (images.size() <= static_cast<std::size_t>(index)) images.resize(static_cast<std::size_t>(index) + 1);
  if (bytes != nullptr && size > 0) images[static_cast<std::size_t>(index)].assign(bytes, bytes + size);
  return true;
}

bool starts_with_glb_magic(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 4> magic{};
  in.read(magic.data(), magic.size());
  return in.gcount() == 4 && std::memcmp(magic.data(), "glTF", 4) == 0;
}

bool is_data_uri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

Result<std::unique_ptr<Document::Impl>> read_gltf(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return fail("no such file");
  if (auto ok = gltf::check_json_depth(path); !ok) return std::unexpected(ok.error());
  auto impl = std::make_unique<Document::Impl>();
  tinygltf::TinyGLTF context;
  gltf::install_safe_file_access(context);
  context.SetImageLoader(&keep_image_bytes, &impl->image_bytes);
  std::string err;
  std::string warn;
  const bool binary = starts_with_glb_magic(path);
  const bool ok = binary ? context.LoadBinaryFromFile(&impl->model, &err, &warn, path)
                         : context.LoadASCIIFromFile(&impl->model, &err, &warn, path);
  if (!ok) return fail(one_line(err));
  impl->image_bytes.resize(impl->model.images.size());
  auto walk = walk_model(impl->model);
  if (!walk) return std::unexpected(walk.error());
  impl->walk = std::move(*walk);
  impl->from_gltf = true;
  impl->source_path = path;
  impl->base_folder = std::filesystem::path(path).parent_path().string();
  impl->input_files.push_back(path);
  const std::filesystem::path folder(impl->base_folder);
  bool all_embedded = !binary && !impl->model.buffers.empty();
  for (const tinygltf::Buffer& buffer : impl->model.buffers) {
    if (!buffer.uri.empty() && !is_data_uri(buffer.uri)) {
      all_embedded = false;
      impl->input_files.push_back((folder / buffer.uri).string());
    }
  }
  impl->embedded_buffers = all_embedded;
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
  auto walk = walk_model(impl->model);
  if (!walk) return fail(scene.name + ": " + walk.error().message);
  impl->walk = std::move(*walk);
  impl->name = scene.name;
  impl->walk.scene.name = scene.name;
  impl->walk.scene.report = scene.report;  // what the original loader skipped
  return Document(std::move(impl));
}

Result<Document> Document::open(const std::string& name_or_path, const ConvertOptions& convert) {
  const std::string ext = lower_extension(name_or_path);
  const std::vector<std::string> builtins = builtin_scene_names();
  const bool builtin = std::find(builtins.begin(), builtins.end(), name_or_path) != builtins.end();
  if (builtin || (ext != ".gltf" && ext != ".glb")) {
    Result<Scene> scene = open_scene(name_or_path);
    if (!scene) return std::unexpected(scene.error());
    Result<Document> document = from_scene(*scene, convert);
    if (document && !builtin) document->impl_->input_files.push_back(name_or_path);
    return document;
  }
  Result<std::unique_ptr<Impl>> impl;
  // tinygltf and the standard library may throw (bad_alloc on a hostile count, json errors).
  try {
    impl = read_gltf(name_or_path);
  } catch (const std::exception& e) {
    impl = fail(one_line(e.what()));
  } catch (...) {
    impl = fail("unknown error while reading glTF");
  }
  if (!impl) return fail(name_or_path + ": " + impl.error().message);
  (*impl)->name = std::filesystem::path(name_or_path).stem().string();
  (*impl)->walk.scene.name = (*impl)->name;
  return Document(std::move(*impl));
}

}  // namespace exao::bake
