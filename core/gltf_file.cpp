#include "core/gltf_file.h"

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/gltf_model.h"

namespace exao::gltf {

bool is_glb(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 4> magic{};
  in.read(magic.data(), magic.size());
  return in.gcount() == 4 && std::memcmp(magic.data(), "glTF", 4) == 0;
}

Result<tinygltf::Model> read_file(const std::string& path, tinygltf::LoadImageDataFunction images, void* user) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return fail("no such file");
  tinygltf::TinyGLTF context;
  context.SetImageLoader(images, user);
  tinygltf::Model model;
  std::string err;
  std::string warn;
  const bool ok = is_glb(path) ? context.LoadBinaryFromFile(&model, &err, &warn, path)
                               : context.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) return fail(one_line(err));
  return model;
}

}  // namespace exao::gltf
