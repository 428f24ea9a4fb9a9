#include "io/gltf_file.h"

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <utility>

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

Result<File> read_file(const std::string& path, tinygltf::LoadImageDataFunction images, void* user) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return fail("no such file");
  // Before any parser sees the JSON: tinygltf and the compression patch both recurse on it.
  if (auto ok = check_json_depth(path); !ok) return std::unexpected(ok.error());
  tinygltf::TinyGLTF context;
  install_safe_file_access(context);  // buffer and image URIs: regular files only
  context.SetImageLoader(images, user);
  File file;
  file.binary = is_glb(path);
  std::string err;
  std::string warn;
  if (!load_file(context, file.model, err, warn, path, file.binary)) return fail(one_line(err));
  for (const tinygltf::Buffer& buffer : file.model.buffers) file.buffer_uris.push_back(buffer.uri);
  Result<std::vector<std::string>> decoded = decode_compression(file.model);
  if (!decoded) return std::unexpected(decoded.error());
  file.notes = std::move(*decoded);
  return file;
}

}  // namespace exao::gltf
