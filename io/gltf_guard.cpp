#include "io/gltf_guard.h"

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "core/file_kind.h"
#include "io/glb_container.h"

namespace exao::gltf {
namespace {

// Scanner state carried across the blocks of a streamed file.
struct DepthScan {
  std::size_t depth = 0;
  std::size_t deepest = 0;
  bool in_string = false;
  bool escaped = false;

  // Returns false once `limit` is passed: the caller may stop reading.
  bool feed(std::string_view bytes, std::size_t limit) {
    for (const char c : bytes) {
      if (in_string) {
        if (escaped) {
          escaped = false;
        } else if (c == '\\') {
          escaped = true;
        } else if (c == '"') {
          in_string = false;
        }
      } else if (c == '"') {
        in_string = true;
      } else if (c == '[' || c == '{') {
        if (++depth > deepest) deepest = depth;
        if (deepest > limit) return false;
      } else if ((c == ']' || c == '}') && depth > 0) {
        --depth;
      }
    }
    return true;
  }
};

bool exists(const std::string& path, void*) {
  std::error_code ec;
  // Never opens the file: opening a FIFO to test it would block.
  return std::filesystem::exists(path, ec);
}

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  if (const std::string problem = not_a_regular_file(path); !problem.empty()) {
    if (err) *err += path + ": " + problem + "\n";
    return false;
  }
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  if (ec || !in) {
    if (err) *err += path + ": cannot open\n";
    return false;
  }
  out->resize(static_cast<std::size_t>(size));
  in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size) {
    if (err) *err += path + ": cannot read all " + std::to_string(size) + " bytes\n";
    return false;
  }
  return true;
}

}  // namespace

std::size_t json_depth(std::string_view json, std::size_t limit) {
  DepthScan scan;
  scan.feed(json, limit);
  return scan.deepest;
}

Result<void> check_json_depth(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};  // the loader reports it
  std::array<unsigned char, 20> header{};
  in.read(reinterpret_cast<char*>(header.data()), header.size());
  const auto got = static_cast<std::size_t>(in.gcount());
  DepthScan scan;
  std::vector<char> block(1 << 16);
  // GLB (glTF 2.0 section 4.4): 12-byte header, then the JSON chunk's length and type.
  if (got >= 4 && std::memcmp(header.data(), "glTF", 4) == 0) {
    if (got < header.size() || glb_word(header.data() + 16) != kJsonChunk) return {};
    std::uint64_t left = glb_word(header.data() + 12);
    while (left > 0 && in) {
      in.read(block.data(), static_cast<std::streamsize>(std::min<std::uint64_t>(left, block.size())));
      const auto n = static_cast<std::size_t>(in.gcount());
      if (n == 0) break;
      left -= n;
      if (!scan.feed({block.data(), n}, kMaxJsonDepth)) break;
    }
  } else {
    bool going = scan.feed({reinterpret_cast<const char*>(header.data()), got}, kMaxJsonDepth);
    while (going && in) {
      in.read(block.data(), static_cast<std::streamsize>(block.size()));
      const auto n = static_cast<std::size_t>(in.gcount());
      if (n == 0) break;
      going = scan.feed({block.data(), n}, kMaxJsonDepth);
    }
  }
  if (scan.deepest > kMaxJsonDepth) {
    return fail("JSON nests deeper than " + std::to_string(kMaxJsonDepth) +
                " levels of arrays and objects (exao's limit; real files nest fewer than 20)");
  }
  return {};
}

void install_safe_file_access(tinygltf::TinyGLTF& context) {
  tinygltf::FsCallbacks callbacks{};
  callbacks.FileExists = &exists;
  callbacks.ExpandFilePath = &tinygltf::ExpandFilePath;
  callbacks.ReadWholeFile = &read_whole_file;
  callbacks.WriteWholeFile = &tinygltf::WriteWholeFile;
  callbacks.user_data = nullptr;
  context.SetFsCallbacks(callbacks);
}

}  // namespace exao::gltf
