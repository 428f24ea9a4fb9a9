// The glTF loader's direct accessor reads (io/gltf_model.h, AccessorPath::Direct) against the
// generic reading through read_accessor's doubles, on generated files: every index type and none,
// packed, interleaved and padded strides, accessor offsets, quantized and sparse positions, strips
// and fans, several meshes and nodes with matrices, TRS, mirroring and GPU instancing, and vertices
// that are -0, NaN, beyond the coordinate limit or repeated. The scenes must be equal bit for bit,
// and hostile files (truncated buffers, indices out of range) refused alike, in one line naming
// the file.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "io/gltf_cutouts.h"
#include "io/gltf_file.h"
#include "io/gltf_walk.h"
#include "io/load_scene.h"
#include "tests/gltf_writer.h"
#include "tests/scene_equality.h"
#include "tests/test_support.h"

namespace exao {
namespace {

using test::bytes;
using test::GltfWriter;

constexpr int kShort = 5122;
constexpr int kNone = 0;  // no indices

enum class Layout { Packed, Interleaved, Padded, Offset };

struct Variant {
  int index_type = test::kUInt;  // or kNone
  Layout layout = Layout::Packed;
  int mode = 4;                  // triangles, 5 strip, 6 fan
  int position_type = test::kFloat;
  bool sparse = false;           // sparse positions over the base values
};

// Vertices in [-1, 1] with the awkward values a loader must keep as they are: -0, NaN, one
// beyond the coordinate limit, and a repeated vertex (zero-area triangles).
std::vector<float> random_positions(std::mt19937& rng, std::size_t count) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> xyz(3 * count);
  for (float& x : xyz) x = u(rng);
  xyz[1] = -0.0f;
  xyz[5] = std::numeric_limits<float>::quiet_NaN();
  xyz[9] = 1e30f;
  for (int k = 0; k < 3; ++k) xyz[3 * 7 + k] = xyz[3 * 6 + k];
  return xyz;
}

// `values` as integers of the component type (sizes 1, 2 or 4 bytes).
std::string integers(const std::vector<std::uint32_t>& values, int type) {
  std::string out;
  for (const std::uint32_t v : values) {
    if (type == test::kUByte) out += bytes(std::vector<std::uint8_t>{static_cast<std::uint8_t>(v)});
    else if (type == test::kUShort) out += bytes(std::vector<std::uint16_t>{static_cast<std::uint16_t>(v)});
    else out += bytes(std::vector<std::uint32_t>{v});
  }
  return out;
}

// The POSITION accessor of `xyz` in the variant's type and layout.
int add_positions(GltfWriter& w, const Variant& v, const std::vector<float>& xyz, std::mt19937& rng) {
  const std::size_t count = xyz.size() / 3;
  std::string element_bytes;  // count elements, tightly packed
  std::size_t element = 12;
  std::string extra;
  if (v.position_type == test::kFloat) {
    element_bytes = bytes(xyz);
  } else {
    std::vector<std::int16_t> q;
    for (const float x : xyz) q.push_back(static_cast<std::int16_t>(std::isfinite(x) ? std::fmod(x, 1.0f) * 32767.0f : 5));
    q[0] = -32768;  // decodes to max(-32768 / 32767, -1) = -1
    element_bytes = bytes(q);
    element = 6;
    extra = ",\"normalized\":true";
  }
  std::string data;
  int stride = 0;
  std::size_t offset = 0;
  switch (v.layout) {
    case Layout::Packed: data = element_bytes; break;
    case Layout::Offset:
      offset = 8;
      data = std::string(offset, '\x55') + element_bytes;
      break;
    case Layout::Interleaved:
    case Layout::Padded: {
      // Interleaved with a NORMAL-sized block after each position (stride 24 for floats), or
      // padded to a stride that is no multiple of the element (20 for floats, 16 for shorts).
      stride = static_cast<int>(v.layout == Layout::Interleaved ? 2 * element : (element + 8 + 3) / 4 * 4);
      for (std::size_t i = 0; i < count; ++i) {
        data += element_bytes.substr(i * element, element);
        data += std::string(static_cast<std::size_t>(stride) - element, static_cast<char>(rng() & 0xFF));
      }
      break;
    }
  }
  if (offset != 0) extra += ",\"byteOffset\":" + std::to_string(offset);
  if (v.sparse) {
    // Three vertices replaced, the last of them twice (the later entry wins).
    const std::vector<std::uint32_t> targets{2, static_cast<std::uint32_t>(count - 1), 2};
    std::vector<float> values{0.25f, 0.5f, 0.75f, -1.0f, -0.0f, 2.0f, 0.125f, 0.375f, 0.625f};
    std::string value_bytes;
    if (v.position_type == test::kFloat) {
      value_bytes = bytes(values);
    } else {
      std::vector<std::int16_t> q;
      for (const float x : values) q.push_back(static_cast<std::int16_t>(x * 1000.0f));
      value_bytes = bytes(q);
    }
    const int iv = w.view(integers(targets, test::kUShort));
    const int vv = w.view(value_bytes);
    extra += ",\"sparse\":{\"count\":3,\"indices\":{\"bufferView\":" + std::to_string(iv) +
             ",\"componentType\":" + std::to_string(test::kUShort) + "},\"values\":{\"bufferView\":" +
             std::to_string(vv) + "}}";
  }
  return w.accessor(w.view(data, stride), v.position_type, count, "VEC3", extra);
}

// A primitive of `vertices` random vertices and about 3 * `triangles` random indices.
std::string add_primitive(GltfWriter& w, const Variant& v, std::size_t vertices, std::size_t triangles, int material,
                          std::mt19937& rng) {
  const int position = add_positions(w, v, random_positions(rng, vertices), rng);
  std::string p = "{\"attributes\":{\"POSITION\":" + std::to_string(position) + "},\"mode\":" + std::to_string(v.mode) +
                  ",\"material\":" + std::to_string(material);
  if (v.index_type != kNone) {
    std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(vertices - 1));
    std::vector<std::uint32_t> order(3 * triangles + 1);  // one trailing index: noted, ignored
    for (std::uint32_t& i : order) i = pick(rng);
    std::string data = integers(order, v.index_type);
    int stride = 0;
    std::string extra;
    if (v.layout == Layout::Offset) {
      extra = ",\"byteOffset\":4";
      data = std::string(4, '\x7f') + data;
    }
    p += ",\"indices\":" + std::to_string(w.accessor(w.view(data, stride), v.index_type, order.size(), "SCALAR", extra));
  }
  return p + "}";
}

// Two meshes (the variant's, and a second of 8-bit indices) drawn by five nodes: TRS with a child
// drawing the second mesh through a matrix, a mirroring scale, and three GPU instances.
std::string variant_glb(const Variant& v, unsigned seed) {
  std::mt19937 rng(seed);
  GltfWriter w;
  const std::string first = add_primitive(w, v, 300, 400, 0, rng);
  const std::string second = add_primitive(w, v, 40, 30, 1, rng);
  Variant small = v;
  small.index_type = test::kUByte;
  small.mode = 4;
  const std::string third = add_primitive(w, small, 50, 60, 1, rng);
  const int rows = w.accessor(w.view(bytes(std::vector<float>{0, 0, 0, 3, 0, 0, 0, 3, 1})), test::kFloat, 3, "VEC3");
  const std::string members =
      "\"materials\":[{\"doubleSided\":true},{}],"
      "\"meshes\":[{\"primitives\":[" + first + "," + second + "]},{\"primitives\":[" + third + "]}],"
      "\"extensionsUsed\":[\"EXT_mesh_gpu_instancing\"],"
      "\"nodes\":["
      "{\"mesh\":0,\"translation\":[0.5,-2,3],\"rotation\":[0.1,0.7,-0.3,0.64],\"scale\":[1.5,0.25,3],\"children\":[1]},"
      "{\"mesh\":1,\"matrix\":[0,1,0,0, -1,0,0,0, 0,0,1,0, 7,8,9,1]},"
      "{\"mesh\":0,\"scale\":[-1,1,1]},"
      "{\"mesh\":1,\"extensions\":{\"EXT_mesh_gpu_instancing\":{\"attributes\":{\"TRANSLATION\":" + std::to_string(rows) +
      "}}}},"
      "{\"mesh\":0}],"
      "\"scenes\":[{\"nodes\":[0,2,3,4]}],\"scene\":0";
  return w.glb(members);
}

Result<gltf::ModelWalk> walk(const std::string& path, gltf::AccessorPath how) {
  std::vector<std::vector<std::uint8_t>> images;
  Result<gltf::File> file = gltf::read_file(path, &gltf::keep_image_bytes, &images);
  if (!file) return std::unexpected(file.error());
  return gltf::walk_model(file->bytes(), how);
}

void expect_same_walk(const gltf::ModelWalk& got, const gltf::ModelWalk& want) {
  test::expect_same_scene(got.scene, want.scene);
  ASSERT_EQ(got.primitives.size(), want.primitives.size());
  for (std::size_t p = 0; p < got.primitives.size(); ++p) {
    const auto& a = got.primitives[p].positions;
    const auto& b = want.primitives[p].positions;
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::dvec3)), 0) << "primitive " << p;
    EXPECT_EQ(got.primitives[p].corners, want.primitives[p].corners) << "primitive " << p;
  }
  ASSERT_EQ(got.triangle_source.size(), want.triangle_source.size());
  for (std::size_t t = 0; t < got.triangle_source.size(); ++t) {
    EXPECT_EQ(got.triangle_source[t].part, want.triangle_source[t].part);
    EXPECT_EQ(got.triangle_source[t].triangle, want.triangle_source[t].triangle);
  }
}

std::string name_of(const Variant& v) {
  const char* layouts[] = {"packed", "interleaved", "padded", "offset"};
  return "indices " + std::to_string(v.index_type) + ", " + layouts[static_cast<int>(v.layout)] + ", mode " +
         std::to_string(v.mode) + ", positions " + std::to_string(v.position_type) + (v.sparse ? ", sparse" : "");
}

TEST(GltfDirect, EqualsTheGenericReadingOnEveryLayout) {
  test::TempDir dir;
  std::vector<Variant> variants;
  for (const int index_type : {kNone, test::kUByte, test::kUShort, test::kUInt}) {
    for (const Layout layout : {Layout::Packed, Layout::Interleaved, Layout::Padded, Layout::Offset}) {
      variants.push_back({index_type, layout, 4, test::kFloat, false});
    }
  }
  variants.push_back({test::kUShort, Layout::Packed, 5, test::kFloat, false});
  variants.push_back({test::kUInt, Layout::Interleaved, 6, test::kFloat, false});
  variants.push_back({test::kUInt, Layout::Packed, 4, kShort, false});
  variants.push_back({test::kUShort, Layout::Padded, 4, kShort, false});
  variants.push_back({test::kUInt, Layout::Packed, 4, test::kFloat, true});
  variants.push_back({kNone, Layout::Interleaved, 4, kShort, true});
  for (std::size_t i = 0; i < variants.size(); ++i) {
    const Variant& v = variants[i];
    SCOPED_TRACE(name_of(v));
    const std::string path = (dir / ("variant" + std::to_string(i) + ".glb")).string();
    test::write_file(path, variant_glb(v, static_cast<unsigned>(21 + i)));
    const Result<gltf::ModelWalk> direct = walk(path, gltf::AccessorPath::Direct);
    const Result<gltf::ModelWalk> generic = walk(path, gltf::AccessorPath::Generic);
    ASSERT_TRUE(direct.has_value()) << direct.error().message;
    ASSERT_TRUE(generic.has_value()) << generic.error().message;
    EXPECT_GT(generic->scene.report.zero_area_skipped + generic->scene.report.non_finite_skipped, 0u);
    expect_same_walk(*direct, *generic);
    // And the loader end to end (the file mapped, cut-outs, notes, name).
    const Result<Scene> loaded = load_gltf(path);
    ASSERT_TRUE(loaded.has_value()) << loaded.error().message;
    test::expect_same_scene(*loaded, generic->scene);
  }
}

// A hostile file is refused by both readings with the same words, and by the loader in one line
// that names the file.
void expect_refused(const std::string& path, const std::string& contains) {
  const Result<gltf::ModelWalk> direct = walk(path, gltf::AccessorPath::Direct);
  const Result<gltf::ModelWalk> generic = walk(path, gltf::AccessorPath::Generic);
  ASSERT_FALSE(direct.has_value());
  ASSERT_FALSE(generic.has_value());
  EXPECT_EQ(direct.error().message, generic.error().message);
  const Result<Scene> loaded = load_gltf(path);
  ASSERT_FALSE(loaded.has_value());
  const std::string& message = loaded.error().message;
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_NE(message.find(contains), std::string::npos) << message;
}

TEST(GltfDirect, HostileFilesAreRefusedAlike) {
  test::TempDir dir;
  const std::vector<float> square{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const auto file = [&](const std::string& name, int index_type, const std::vector<std::uint32_t>& order,
                        const std::string& position_view) {
    GltfWriter w;
    const int packed = w.view(bytes(square));
    const int view = position_view.empty() ? packed : w.raw_view(position_view);
    const int position = w.accessor(view, test::kFloat, 4, "VEC3");
    const int indices = w.accessor(w.view(integers(order, index_type)), index_type, order.size(), "SCALAR");
    const std::string path = (dir / name).string();
    test::write_file(path, w.glb("\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(position) +
                                 "},\"indices\":" + std::to_string(indices) +
                                 "}]}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]"));
    return path;
  };
  for (const int type : {test::kUByte, test::kUShort, test::kUInt}) {
    SCOPED_TRACE(type);
    expect_refused(file("range" + std::to_string(type) + ".glb", type, {0, 1, 2, 0, 2, 4}, ""),
                   "mesh 0 primitive 0: index 4 >= vertex count 4");
  }
  // Positions past their view, a view past the buffer, a stride shorter than an element.
  expect_refused(file("short_view.glb", test::kUInt, {0, 1, 2}, "{\"buffer\":0,\"byteOffset\":0,\"byteLength\":40}"),
                 "exceeds its buffer view");
  expect_refused(file("past_buffer.glb", test::kUInt, {0, 1, 2}, "{\"buffer\":0,\"byteOffset\":4,\"byteLength\":4800}"),
                 "exceeds buffer 0");
  expect_refused(file("stride.glb", test::kUInt, {0, 1, 2}, "{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48,\"byteStride\":8}"),
                 "byteStride 8 is less than an element");
  // An image whose view lies past the buffer: tinygltf hands its callback the bytes unchecked.
  {
    GltfWriter w;
    const int position = w.positions(square);
    const int image = w.raw_view("{\"buffer\":0,\"byteOffset\":16,\"byteLength\":5000000}");
    const std::string path = (dir / "image_past_buffer.glb").string();
    test::write_file(path, w.glb("\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(position) +
                                 "}}]}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}],\"images\":[{\"bufferView\":" +
                                 std::to_string(image) + ",\"mimeType\":\"image/png\"}]"));
    expect_refused(path, "image 0: buffer view 1 lies outside its buffer");
  }
  // A GLB cut short inside its BIN chunk.
  const std::string whole = variant_glb(Variant{}, 5);
  const std::string cut = (dir / "cut.glb").string();
  test::write_file(cut, whole.substr(0, whole.size() - 100));
  const Result<Scene> loaded = load_gltf(cut);
  ASSERT_FALSE(loaded.has_value());
  EXPECT_NE(loaded.error().message.find(cut), std::string::npos) << loaded.error().message;
  EXPECT_EQ(loaded.error().message.find('\n'), std::string::npos) << loaded.error().message;
}

}  // namespace
}  // namespace exao

namespace exao {
namespace {

// --- A GLB's mesh bytes read in place (io/glb_in_place.h) -----------------------------------

struct Read {
  gltf::File file;
  std::vector<std::vector<std::uint8_t>> images;
};

Read read(const std::string& path, gltf::BinChunk bin) {
  Read out;
  Result<gltf::File> file = gltf::read_file(path, &gltf::keep_image_bytes, &out.images, bin);
  EXPECT_TRUE(file.has_value()) << file.error().message;
  if (file) out.file = std::move(*file);
  return out;
}

// The loader's reading (in place) walks to the scene the bake's reading (copied) walks to, and
// keeps the same image bytes.
void expect_in_place_equals_copied(const std::string& path) {
  SCOPED_TRACE(path);
  const Read in_place = read(path, gltf::BinChunk::InPlace);
  const Read copied = read(path, gltf::BinChunk::Copied);
  EXPECT_EQ(copied.file.mapped, nullptr);
  EXPECT_EQ(in_place.images, copied.images);
  const Result<gltf::ModelWalk> a = gltf::walk_model(in_place.file.bytes());
  const Result<gltf::ModelWalk> b = gltf::walk_model(copied.file.bytes());
  ASSERT_TRUE(a.has_value()) << a.error().message;
  ASSERT_TRUE(b.has_value()) << b.error().message;
  test::expect_same_scene(a->scene, b->scene);
  const Result<Scene> loaded = load_gltf(path);
  ASSERT_TRUE(loaded.has_value()) << loaded.error().message;
  test::expect_same_scene(*loaded, b->scene);
}

TEST(GlbInPlace, TinygltfGetsOnlyTheImagesAndTheMeshIsReadFromTheFile) {
  test::TempDir dir;
  const std::vector<float> square{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::string image = "not decoded: a cut-out would need it";  // kept encoded, never decoded here
  const auto file = [&](const std::string& name, bool image_first, bool with_image, const std::string& more) {
    GltfWriter w;
    const int first = image_first && with_image ? w.view(image) : -1;
    const int position = w.positions(square);
    const int indices = w.indices(std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}, test::kUInt);
    const int last = !image_first && with_image ? w.view(image) : -1;
    std::string members = "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(position) +
                          "},\"indices\":" + std::to_string(indices) +
                          "}]}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]" + more;
    if (with_image) members += ",\"images\":[{\"bufferView\":" + std::to_string(std::max(first, last)) + ",\"mimeType\":\"image/png\"}]";
    const std::string path = (dir / name).string();
    test::write_file(path, w.glb(members));
    return path;
  };
  const std::size_t mesh = 4 * 12 + 4 * 6;  // positions and indices
  const struct {
    std::string path;
    std::size_t kept;   // what tinygltf copies into buffer 0: up to the image's end, at least a byte
    std::size_t whole;  // buffer 0
  } cases[] = {{file("image_first.glb", true, true, ""), image.size(), mesh + image.size()},
               {file("image_last.glb", false, true, ""), mesh + image.size(), mesh + image.size()},
               {file("no_image.glb", false, false, ""), 1, mesh}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.path);
    const Read r = read(c.path, gltf::BinChunk::InPlace);
    EXPECT_NE(r.file.mapped, nullptr) << "read in place";
    ASSERT_FALSE(r.file.model.buffers.empty());
    EXPECT_EQ(r.file.model.buffers[0].data.size(), c.kept);
    EXPECT_EQ(r.file.bytes().buffer(0).size(), c.whole);
    expect_in_place_equals_copied(c.path);
  }
  // A file that names a compression extension is read whole: its decoders rewrite the buffers.
  const std::string compressed = file("compressed_named.glb", false, true, ",\"extensionsUsed\":[\"EXT_meshopt_compression\"]");
  EXPECT_EQ(read(compressed, gltf::BinChunk::InPlace).file.mapped, nullptr);
  expect_in_place_equals_copied(compressed);
  // Hostile layouts are refused in place with the copy's words (HostileFilesAreRefusedAlike
  // runs the loader, which reads in place, against the walk of the copy).
}

TEST(GlbInPlace, RealAssetsLoadAsTheirCopies) {
  int found = 0;
  for (const char* name : {"Box/glTF-Binary/Box.glb", "BoxInterleaved/glTF-Binary/BoxInterleaved.glb", "Duck/glTF-Binary/Duck.glb",
                           "Fox/glTF-Binary/Fox.glb", "NegativeScaleTest/glTF-Binary/NegativeScaleTest.glb",
                           "OrientationTest/glTF-Binary/OrientationTest.glb",
                           "SimpleInstancing/glTF-Binary/SimpleInstancing.glb"}) {
    const auto path = test::real_scene(name);
    if (!std::filesystem::exists(path)) continue;
    ++found;
    EXPECT_NE(read(path.string(), gltf::BinChunk::InPlace).file.mapped, nullptr) << name << " read in place";
    expect_in_place_equals_copied(path.string());
  }
  if (found == 0) GTEST_SKIP() << "the shared scenes are not here";
}

}  // namespace
}  // namespace exao
