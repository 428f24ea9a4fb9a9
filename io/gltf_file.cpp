#include "io/gltf_file.h"

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <utility>

#include "io/glb_in_place.h"
#include "io/gltf_compression.h"
#include "io/gltf_guard.h"
#include "io/gltf_model.h"

namespace exao::gltf {

bool is_glb(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 4> magic{};
  in.read(magic.data(), magic.size());
  return in.gcount() == 4 && std::memcmp(magic.data(), "glTF", 4) == 0;
}

namespace {

// The caller's image callback behind a bounds check. tinygltf 2.7 hands an image in a buffer view
// to the callback as &buffer.data[byteOffset] and byteLength without checking either against the
// buffer, so a view past the end made the callback read past it (a crash on a 1 KB file). The
// buffers and views are parsed before the images, so they can be checked here.
struct ImageGuard {
  const tinygltf::Model* model = nullptr;  // the model being loaded
  tinygltf::LoadImageDataFunction images = nullptr;
  void* user = nullptr;
};

// Whether buffer view `v` lies inside its buffer's bytes.
bool view_inside_buffer(const tinygltf::Model& model, int v) {
  if (v < 0 || static_cast<std::size_t>(v) >= model.bufferViews.size()) return false;
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(v)];
  if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) return false;
  const std::size_t size = model.buffers[static_cast<std::size_t>(view.buffer)].data.size();
  return view.byteOffset <= size && view.byteLength <= size - view.byteOffset;
}

bool guarded_image(tinygltf::Image* image, int index, std::string* err, std::string* warn, int width, int height,
                   const unsigned char* bytes, int size, void* user) {
  const ImageGuard& guard = *static_cast<const ImageGuard*>(user);
  const int v = image != nullptr ? image->bufferView : -1;
  if (v >= 0 && !view_inside_buffer(*guard.model, v)) {
    if (err) *err += "image " + std::to_string(index) + ": buffer view " + std::to_string(v) + " lies outside its buffer\n";
    return false;
  }
  if (guard.images == nullptr) return true;  // images not wanted: nothing is read
  return guard.images(image, index, err, warn, width, height, bytes, size, guard.user);
}

// Loads `path`'s model as tinygltf would, but with buffer 0's bytes left in the mapped file
// (io/glb_in_place.h): tinygltf's result, or nothing, with `file` unchanged, when the file does
// not qualify.
std::optional<bool> load_in_place(tinygltf::TinyGLTF& context, const std::string& path, File& file, std::string& err,
                                  std::string& warn) {
  auto mapped = std::make_shared<const MappedFile>(path);
  if (!mapped->ok()) return std::nullopt;
  const std::string_view bytes = mapped->bytes();
  const std::optional<GlbInPlace> in_place =
      glb_in_place({reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()});
  if (!in_place || in_place->container.size() > std::numeric_limits<unsigned int>::max()) return std::nullopt;
  const std::string base = std::filesystem::path(path).parent_path().string();
  const bool loaded = context.LoadBinaryFromMemory(&file.model, &err, &warn, in_place->container.data(),
                                                   static_cast<unsigned int>(in_place->container.size()),
                                                   base.empty() ? "." : base);
  file.buffer0_in_place = in_place->buffer0;
  file.mapped = std::move(mapped);
  return loaded;
}

}  // namespace

Result<File> read_file(const std::string& path, tinygltf::LoadImageDataFunction images, void* user, BinChunk bin) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return fail("no such file");
  // Before any parser sees the JSON: tinygltf and the compression patch both recurse on it.
  if (auto ok = check_json_depth(path); !ok) return std::unexpected(ok.error());
  tinygltf::TinyGLTF context;
  install_safe_file_access(context);  // buffer and image URIs: regular files only
  File file;
  ImageGuard guard{&file.model, images, user};
  context.SetImageLoader(&guarded_image, &guard);
  file.binary = is_glb(path);
  std::string err;
  std::string warn;
  std::optional<bool> loaded;
  if (bin == BinChunk::InPlace && file.binary) loaded = load_in_place(context, path, file, err, warn);
  if (!loaded) loaded = load_file(context, file.model, err, warn, path, file.binary);
  if (!*loaded) return fail(one_line(err));
  for (const tinygltf::Buffer& buffer : file.model.buffers) file.buffer_uris.push_back(buffer.uri);
  Result<std::vector<std::string>> decoded = decode_compression(file.model);
  if (!decoded) return std::unexpected(decoded.error());
  file.notes = std::move(*decoded);
  return file;
}

}  // namespace exao::gltf
