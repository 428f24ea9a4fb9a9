#include "bake/save.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bake/document_impl.h"
#include "bake/gltf_access.h"
#include "bake/png_encode.h"
#include "core/atomic_write.h"
#include "io/image_io.h"

namespace exao::bake {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string base64(std::span<const std::uint8_t> bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t b0 = bytes[i];
    const std::uint32_t b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0u;
    const std::uint32_t b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0u;
    const std::uint32_t v = b0 << 16 | b1 << 8 | b2;
    out += kDigits[v >> 18 & 63];
    out += kDigits[v >> 12 & 63];
    out += i + 1 < bytes.size() ? kDigits[v >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[v & 63] : '=';
  }
  return out;
}

// Images keep the URI they had: tinygltf would otherwise re-encode pixels the bake never decoded.
bool keep_uri(const std::string*, const std::string*, const tinygltf::Image*, bool, std::string*, void*) { return false; }

Result<void> check_not_input(const Document& document, const std::string& path) {
  std::error_code ec;
  for (const std::string& input : document.input_files()) {
    if (fs::exists(input, ec) && fs::exists(path, ec) && fs::equivalent(input, path, ec)) {
      return fail(path + ": is a file of the input scene; refusing to overwrite it");
    }
  }
  return {};
}

struct Paths {
  std::string gltf;
  std::string bin;                   // empty: no external buffer
  std::vector<std::string> png, exr;  // per map
  bool binary = false;
};

Result<Paths> paths_for(const Document& document, const BakeResult* result, const SaveOptions& options) {
  Paths out;
  const fs::path path(options.path);
  const std::string ext = lower(path.extension().string());
  if (ext != ".gltf" && ext != ".glb") {
    return fail(options.path + ": the output must be a .gltf or a .glb file");
  }
  out.gltf = options.path;
  out.binary = ext == ".glb";
  const fs::path stem = path.parent_path() / path.stem();
  if (!out.binary && !document.impl().embedded_buffers) out.bin = stem.string() + ".bin";
  if (result != nullptr) {
    for (const AoMap& map : result->maps) {
      const std::string base = stem.string() + "_ao" + (map.label.empty() ? "" : "_" + map.label);
      out.png.push_back(base + ".png");
      out.exr.push_back(base + ".exr");
    }
  }
  return out;
}

std::vector<std::string> all(const Paths& p) {
  std::vector<std::string> out;
  for (std::size_t m = 0; m < p.png.size(); ++m) {
    out.push_back(p.png[m]);
    out.push_back(p.exr[m]);
  }
  if (!p.bin.empty()) out.push_back(p.bin);
  out.push_back(p.gltf);
  return out;
}

std::string mime_for(const std::string& uri) {
  const std::string ext = lower(fs::path(uri).extension().string());
  if (ext == ".png") return "image/png";
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  return "";
}

// Step 1: the maps as PNG (also embedded in a .glb) and OpenEXR; returns each map's PNG bytes.
Result<std::vector<std::vector<std::uint8_t>>> write_maps(const BakeResult& result, const Paths& paths,
                                                          const SaveOptions& options, std::vector<std::string>& written) {
  std::vector<std::vector<std::uint8_t>> map_png(result.maps.size());
  for (std::size_t m = 0; m < result.maps.size(); ++m) {
    const AoMap& map = result.maps[m];
    auto png = encode_grey_png(map.ao, map.size, map.size, options.png_bits);
    if (!png) return std::unexpected(png.error());
    map_png[m] = std::move(*png);
    if (auto ok = write_file_atomically(paths.png[m], map_png[m]); !ok) return std::unexpected(ok.error());
    written.push_back(paths.png[m]);
    AoImage exr;
    exr.width = exr.height = map.size;
    exr.ao = map.ao;
    exr.coverage.resize(map.filled.size());
    for (std::size_t i = 0; i < map.filled.size(); ++i) exr.coverage[i] = map.filled[i] == 1 ? 1.0f : 0.0f;
    if (auto ok = write_exr(exr, paths.exr[m]); !ok) return std::unexpected(ok.error());
    written.push_back(paths.exr[m]);
  }
  return map_png;
}

// Step 2: one buffer holding every input buffer, 16-byte aligned so that each view keeps its
// alignment, and views appended to it.
class MergedBuffer {
 public:
  explicit MergedBuffer(tinygltf::Model& model) : model_(model) {
    std::vector<std::size_t> base(model.buffers.size(), 0);
    for (std::size_t b = 0; b < model.buffers.size(); ++b) {
      bytes_.resize((bytes_.size() + 15) / 16 * 16, 0);
      base[b] = bytes_.size();
      bytes_.insert(bytes_.end(), model.buffers[b].data.begin(), model.buffers[b].data.end());
    }
    for (tinygltf::BufferView& view : model.bufferViews) {
      if (view.buffer >= 0 && static_cast<std::size_t>(view.buffer) < base.size()) {
        view.byteOffset += base[static_cast<std::size_t>(view.buffer)];
        view.buffer = 0;
      }
    }
  }

  /// A new view of `bytes`, 4-byte aligned; its index.
  int add_view(std::span<const std::uint8_t> bytes) {
    bytes_.resize((bytes_.size() + 3) / 4 * 4, 0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bytes_.size();
    view.byteLength = bytes.size();
    bytes_.insert(bytes_.end(), bytes.begin(), bytes.end());
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size() - 1);
  }

  /// The model's buffers become this one (none when nothing refers to a buffer).
  void install() {
    tinygltf::Buffer buffer;
    buffer.data = std::move(bytes_);
    model_.buffers.clear();
    if (!buffer.data.empty() || !model_.bufferViews.empty()) model_.buffers.push_back(std::move(buffer));
  }

 private:
  tinygltf::Model& model_;
  std::vector<unsigned char> bytes_;
};

// Step 3: the input's images as they were (embedded in a .glb, kept or copied beside a .gltf),
// and the maps as new ones.
Result<void> place_images(const Document& document, const BakeResult& result, const Paths& paths,
                          const std::vector<std::vector<std::uint8_t>>& map_png, tinygltf::Model& model,
                          MergedBuffer& buffer, std::vector<std::string>& written, std::vector<std::string>& notes) {
  const Document::Impl& doc = document.impl();
  const fs::path out_folder = fs::path(paths.gltf).parent_path();
  std::error_code ec;
  const bool same_folder = fs::equivalent(out_folder.empty() ? fs::path(".") : out_folder,
                                          doc.base_folder.empty() ? fs::path(".") : fs::path(doc.base_folder), ec);
  for (std::size_t i = 0; i < doc.model.images.size() && i < doc.image_bytes.size(); ++i) {
    tinygltf::Image& image = model.images[i];
    const std::vector<std::uint8_t>& bytes = doc.image_bytes[i];
    if (image.bufferView >= 0) continue;  // moved with the buffers
    if (image.uri.empty()) {              // a data: URI, decoded by the reader
      if (bytes.empty()) continue;
      if (paths.binary) {
        image.bufferView = buffer.add_view(bytes);
      } else {
        image.uri = "data:" + (image.mimeType.empty() ? std::string("image/png") : image.mimeType) + ";base64," + base64(bytes);
      }
      continue;
    }
    if (bytes.empty()) continue;  // missing beside the input: the reference stays (Document notes it)
    const std::string mime = mime_for(image.uri);
    if (paths.binary && !mime.empty()) {
      image.bufferView = buffer.add_view(bytes);
      image.mimeType = mime;
      image.uri.clear();
      continue;
    }
    if (same_folder) continue;
    const fs::path target = out_folder / image.uri;
    if (fs::exists(target, ec)) {
      std::ifstream in(target, std::ios::binary);
      const std::vector<std::uint8_t> existing((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (existing != bytes) notes.push_back(target.string() + " exists and differs from the input's image: kept as it is");
      continue;
    }
    if (auto ok = check_not_input(document, target.string()); !ok) return std::unexpected(ok.error());
    fs::create_directories(target.parent_path(), ec);
    if (auto ok = write_file_atomically(target.string(), bytes); !ok) return std::unexpected(ok.error());
    written.push_back(target.string());
  }
  for (std::size_t m = 0; m < result.maps.size(); ++m) {
    tinygltf::Image& image = model.images[static_cast<std::size_t>(result.maps[m].image)];
    if (paths.binary) {
      image.bufferView = buffer.add_view(map_png[m]);
      image.mimeType = "image/png";
      image.uri.clear();
    } else {
      image.uri = fs::path(paths.png[m]).filename().string();
      image.mimeType.clear();
    }
  }
  return {};
}

// Step 4: the glTF JSON. tinygltf writes it (with the buffer left empty); it is then put right
// where tinygltf 2.7 gets it wrong (it writes "zfar": 0 for an infinite projection, which glTF
// forbids) and pointed at its buffer of `bin_size` bytes (none when embedded).
Result<nlohmann::ordered_json> model_json(tinygltf::Model& model, const Paths& paths, bool embed, std::size_t bin_size) {
  tinygltf::TinyGLTF writer;
  writer.SetImageWriter(&keep_uri, nullptr);
  std::ostringstream stream;
  if (!writer.WriteGltfSceneToStream(&model, stream, false, false)) {
    return fail(paths.gltf + ": tinygltf could not serialise the model");
  }
  nlohmann::ordered_json json = nlohmann::ordered_json::parse(stream.str(), nullptr, false);
  if (json.is_discarded()) return fail(paths.gltf + ": tinygltf wrote JSON that does not parse");
  if (json.contains("cameras")) {
    for (auto& camera : json["cameras"]) {
      if (camera.contains("perspective") && camera["perspective"].contains("zfar") &&
          !(camera["perspective"]["zfar"].get<double>() > 0.0)) {
        camera["perspective"].erase("zfar");
      }
    }
  }
  if (!embed && json.contains("buffers") && !json["buffers"].empty()) {
    auto& entry = json["buffers"][0];
    entry["byteLength"] = bin_size;
    if (paths.binary) {
      entry.erase("uri");
    } else {
      entry["uri"] = fs::path(paths.bin).filename().string();
    }
  }
  return json;
}

// Step 5: the file's bytes: GLB (glTF 2.0 section 4.4: a 12-byte header, a JSON chunk padded
// with spaces, a BIN chunk padded with zeros, every chunk 4-byte aligned), or the JSON text.
Result<std::vector<std::uint8_t>> file_bytes(const nlohmann::ordered_json& json, const Paths& paths,
                                             std::vector<unsigned char> bin) {
  std::vector<std::uint8_t> file;
  if (!paths.binary) {
    const std::string text = json.dump(2) + "\n";
    file.assign(text.begin(), text.end());
    return file;
  }
  std::string text = json.dump();
  text.resize((text.size() + 3) / 4 * 4, ' ');
  bin.resize((bin.size() + 3) / 4 * 4, 0);
  const auto put32 = [&](std::uint32_t v) {
    for (int k = 0; k < 4; ++k) file.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  };
  const std::size_t total = 12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size());
  if (total > 0xffffffffu) return fail(paths.gltf + ": too large for a .glb (4 GiB); write a .gltf");
  put32(0x46546C67u);  // "glTF"
  put32(2);
  put32(static_cast<std::uint32_t>(total));
  put32(static_cast<std::uint32_t>(text.size()));
  put32(0x4E4F534Au);  // "JSON"
  file.insert(file.end(), text.begin(), text.end());
  if (!bin.empty()) {
    put32(static_cast<std::uint32_t>(bin.size()));
    put32(0x004E4942u);  // "BIN"
    file.insert(file.end(), bin.begin(), bin.end());
  }
  return file;
}

}  // namespace

Result<std::vector<std::string>> planned_outputs(const Document& document, const BakeResult* result,
                                                 const SaveOptions& options) {
  if (auto ok = check_png_bits(options.png_bits); !ok) return std::unexpected(ok.error());
  auto paths = paths_for(document, result, options);
  if (!paths) return std::unexpected(paths.error());
  std::vector<std::string> out = all(*paths);
  for (const std::string& path : out) {
    if (auto ok = check_not_input(document, path); !ok) return std::unexpected(ok.error());
  }
  return out;
}

Result<std::vector<std::string>> save(const Document& document, const BakeResult& result, const SaveOptions& options,
                                      std::vector<std::string>& notes) {
  auto checked = planned_outputs(document, &result, options);
  if (!checked) return std::unexpected(checked.error());
  auto paths = paths_for(document, &result, options);
  if (!paths) return std::unexpected(paths.error());
  tinygltf::Model model = document.impl().model;
  std::vector<std::string> written;

  auto map_png = write_maps(result, *paths, options, written);
  if (!map_png) return std::unexpected(map_png.error());
  MergedBuffer buffer(model);
  if (auto ok = place_images(document, result, *paths, *map_png, model, buffer, written, notes); !ok) {
    return std::unexpected(ok.error());
  }
  buffer.install();
  const bool embed = !paths->binary && paths->bin.empty();
  std::vector<unsigned char> bin;
  if (!embed && !model.buffers.empty()) bin = std::move(model.buffers[0].data);
  if (!embed && !model.buffers.empty()) model.buffers[0].data.clear();
  auto json = model_json(model, *paths, embed, bin.size());
  if (!json) return std::unexpected(json.error());
  // The glTF last, so that it never refers to a file that is not there yet.
  if (!paths->bin.empty() && !bin.empty()) {
    if (auto ok = write_file_atomically(paths->bin, bin); !ok) return std::unexpected(ok.error());
    written.push_back(paths->bin);
  }
  auto file = file_bytes(*json, *paths, std::move(bin));
  if (!file) return std::unexpected(file.error());
  if (auto ok = write_file_atomically(paths->gltf, *file); !ok) return std::unexpected(ok.error());
  written.push_back(paths->gltf);
  return written;
}

}  // namespace exao::bake
