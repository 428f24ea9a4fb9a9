#include "lut/plane_table.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/atomic_write.h"
#include "core/random.h"
#include "lut/mask_kernels.h"
#include "lut/sample_arrays.h"

namespace exao::lut {
namespace {

// The file stores the masks as the machine's 64-bit words; exao runs on x86-64 (Embree, AVX).
static_assert(std::endian::native == std::endian::little, "plane table files are little-endian");

constexpr char kMagic[8] = {'E', 'X', 'A', 'O', 'L', 'U', 'T', '\0'};
constexpr std::uint32_t kFormatVersion = 1;

// A 64-bit chained hash of words: SplitMix64's finaliser on (state ^ word). Not cryptographic;
// it catches flipped bits, truncation and a file of another pattern.
struct Hasher {
  std::uint64_t state = 0x6A09E667F3BCC908ull;
  void add(std::uint64_t word) { state = mix64(state ^ word); }
};

std::uint64_t checksum_bytes(const unsigned char* bytes, std::size_t size) {
  Hasher h;
  std::size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, bytes + i, 8);
    h.add(w);
  }
  std::uint64_t tail = 0;
  std::memcpy(&tail, bytes + i, size - i);
  h.add(tail ^ (static_cast<std::uint64_t>(size) << 56));
  h.add(size);
  return h.state;
}

// The header, field by field; serialised without padding in this order.
struct Header {
  std::uint32_t version = kFormatVersion;
  std::uint32_t samples = 0;
  std::uint32_t resolution = 0;
  std::uint32_t bits = 0;
  std::uint32_t kind = 0;
  std::uint32_t falloff = 0;
  std::uint64_t seed = 0;
  std::uint64_t pattern_hash = 0;
  std::uint64_t payload_bytes = 0;
  std::uint64_t payload_checksum = 0;
};
constexpr std::size_t kHeaderBytes = sizeof(kMagic) + 6 * 4 + 4 * 8 + 8;  // + the header's own checksum

std::string encode(const Header& h) {
  std::string out(kMagic, sizeof(kMagic));
  const auto put = [&](auto value) { out.append(reinterpret_cast<const char*>(&value), sizeof(value)); };
  put(h.version);
  put(h.samples);
  put(h.resolution);
  put(h.bits);
  put(h.kind);
  put(h.falloff);
  put(h.seed);
  put(h.pattern_hash);
  put(h.payload_bytes);
  put(h.payload_checksum);
  put(checksum_bytes(reinterpret_cast<const unsigned char*>(out.data()), out.size()));
  return out;
}

Header decode(const unsigned char* bytes) {
  Header h;
  std::size_t at = sizeof(kMagic);
  const auto get = [&](auto& value) {
    std::memcpy(&value, bytes + at, sizeof(value));
    at += sizeof(value);
  };
  get(h.version);
  get(h.samples);
  get(h.resolution);
  get(h.bits);
  get(h.kind);
  get(h.falloff);
  get(h.seed);
  get(h.pattern_hash);
  get(h.payload_bytes);
  get(h.payload_checksum);
  return h;
}

std::size_t cube(int resolution) {
  const auto r = static_cast<std::size_t>(resolution);
  return r * r * r;
}

}  // namespace

const char* table_kind_name(TableKind kind) { return name_of(kind); }

Result<void> check_table_resolution(int resolution) {
  if (resolution < kMinTableResolution || resolution > kMaxTableResolution) {
    return fail("table_resolution: must be from " + std::to_string(kMinTableResolution) + " to " +
                std::to_string(kMaxTableResolution) + " (0: the default for N), got " + std::to_string(resolution));
  }
  return {};
}

std::uint64_t pattern_hash(const SamplePattern& pattern) {
  Hasher h;
  h.add(static_cast<std::uint64_t>(pattern.count));
  h.add(static_cast<std::uint64_t>(pattern.falloff));
  h.add(pattern.seed);
  for (std::size_t i = 0; i < pattern.directions.size(); ++i) {
    const glm::vec3 d = pattern.directions[i];
    h.add((std::uint64_t{std::bit_cast<std::uint32_t>(d.x)} << 32) | std::bit_cast<std::uint32_t>(d.y));
    h.add((std::uint64_t{std::bit_cast<std::uint32_t>(d.z)} << 32) | std::bit_cast<std::uint32_t>(pattern.lengths[i]));
  }
  return h.state;
}

PlaneTable& PlaneTable::operator=(PlaneTable&& other) noexcept {
  samples_ = other.samples_;
  resolution_ = other.resolution_;
  bits_ = other.bits_;
  kind_ = other.kind_;
  falloff_ = other.falloff_;
  seed_ = other.seed_;
  pattern_hash_ = other.pattern_hash_;
  cells_ = other.cells_;
  storage_ = std::move(other.storage_);
  base_ = data();
  other.storage_ = std::monostate{};
  other.base_ = nullptr;
  other.cells_ = 0;
  return *this;
}

void PlaneTable::allocate(int samples, int resolution) {
  samples_ = samples;
  resolution_ = resolution;
  bits_ = mask_bits_for(samples);
  cells_ = cube(resolution);
  with_mask_bits(samples, [&](auto bits) { storage_ = std::vector<Mask<decltype(bits)::value>>(cells_); });
  base_ = data();
}

void* PlaneTable::data() {
  return std::visit(
      [](auto& v) -> void* {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) {
          return nullptr;
        } else {
          return v.data();
        }
      },
      storage_);
}

bool PlaneTable::in_outer_shell(std::size_t index) const {
  const auto r = static_cast<std::size_t>(resolution_);
  const std::size_t x = index % r, y = index / r % r, z = index / (r * r);
  return x == 0 || y == 0 || z == 0 || x == r - 1 || y == r - 1 || z == r - 1;
}

Plane PlaneTable::cell_plane(std::size_t index) const {
  const auto r = static_cast<std::size_t>(resolution_);
  const std::size_t ix[3] = {index % r, index / r % r, index / (r * r)};
  // Cell centre in [-1, 1]^3, in double so that every machine stores the same plane.
  glm::dvec3 c;
  for (int k = 0; k < 3; ++k) c[k] = (2.0 * static_cast<double>(ix[k]) + 1.0) / static_cast<double>(r) - 1.0;
  Plane plane;
  if (in_outer_shell(index)) {
    // The d = 0 plane whose address is the middle of the cell's patch of the cube's surface:
    // the centre with its outermost coordinates pushed to +-1. (The 3D centre itself sits half
    // a cell inside, and its direction is up to half a cell off the patch's middle.)
    for (int k = 0; k < 3; ++k) {
      if (ix[k] == 0) c[k] = -1.0;
      if (ix[k] == r - 1) c[k] = 1.0;
    }
    plane.m = glm::vec3(c / std::sqrt(glm::dot(c, c)));
    plane.d = 0.0f;
    return plane;
  }
  const double d_norm = std::max(std::abs(c.x), std::max(std::abs(c.y), std::abs(c.z)));
  plane.m = glm::vec3(c / std::sqrt(glm::dot(c, c)));
  plane.d = static_cast<float>(8.0 / 7.0 * (1.0 - d_norm));
  return plane;
}

Result<PlaneTable> PlaneTable::build(const SamplePattern& pattern, TableKind kind, int resolution) {
  if (resolution == 0) resolution = default_table_resolution(pattern.count);
  if (auto ok = check_table_resolution(resolution); !ok) return std::unexpected(ok.error());
  if (auto ok = check_sample_count(pattern.count); !ok) return std::unexpected(ok.error());

  PlaneTable table;
  table.kind_ = kind;
  table.falloff_ = pattern.falloff;
  table.seed_ = pattern.seed;
  table.pattern_hash_ = lut::pattern_hash(pattern);
  table.allocate(pattern.count, resolution);

  const SampleArrays samples(pattern);
  const bool points = kind == TableKind::Points;
  const float* x = points ? samples.px() : samples.wx();
  const float* y = points ? samples.py() : samples.wy();
  const float* z = points ? samples.pz() : samples.wz();
  with_mask_bits(pattern.count, [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    auto* masks = static_cast<Mask<Bits>*>(table.data());
    // One row of R cells per task item: cells are independent, rows keep the writes contiguous.
    const std::size_t rows = static_cast<std::size_t>(resolution) * static_cast<std::size_t>(resolution);
    const auto plane_mask = mask_kernels(default_isa()).get<Bits>().plane_mask;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t row = range.begin(); row != range.end(); ++row) {
        const std::size_t first = row * static_cast<std::size_t>(resolution);
        for (std::size_t i = first; i < first + static_cast<std::size_t>(resolution); ++i) {
          masks[i] = plane_mask(x, y, z, table.cell_plane(i));
        }
      }
    });
  });
  return table;
}

Result<void> PlaneTable::save(const std::string& path) const {
  if (!base_) return fail(path + ": cannot save an empty plane table");
  Header h;
  h.samples = static_cast<std::uint32_t>(samples_);
  h.resolution = static_cast<std::uint32_t>(resolution_);
  h.bits = static_cast<std::uint32_t>(bits_);
  h.kind = static_cast<std::uint32_t>(kind_);
  h.falloff = static_cast<std::uint32_t>(falloff_);
  h.seed = seed_;
  h.pattern_hash = pattern_hash_;
  h.payload_bytes = memory_bytes();
  h.payload_checksum = checksum_bytes(static_cast<const unsigned char*>(base_), memory_bytes());
  const std::string header = encode(h);
  return write_atomically(path, [&](const std::string& temp) -> Result<void> {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(static_cast<const char*>(base_), static_cast<std::streamsize>(memory_bytes()));
    if (!out.flush()) return fail(path + ": write failed: " + system_reason());
    return {};
  });
}

Result<PlaneTable> PlaneTable::load(const std::string& path, const SamplePattern& expected, TableKind kind,
                                    int resolution) {
  if (resolution == 0) resolution = default_table_resolution(expected.count);
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(path + ": cannot open the plane table");
  unsigned char head[kHeaderBytes];
  in.read(reinterpret_cast<char*>(head), static_cast<std::streamsize>(kHeaderBytes));
  const auto got = static_cast<std::size_t>(in.gcount());
  if (got < sizeof(kMagic) || std::memcmp(head, kMagic, sizeof(kMagic)) != 0) {
    return fail(path + ": not an exao plane table (bad magic)");
  }
  // The version first: a newer format may lay out (and checksum) its header differently.
  std::uint32_t version = 0;
  if (got >= sizeof(kMagic) + sizeof(version)) std::memcpy(&version, head + sizeof(kMagic), sizeof(version));
  if (got >= sizeof(kMagic) + sizeof(version) && version != kFormatVersion) {
    return fail(path + ": plane table format version " + std::to_string(version) + ", this exao reads version " +
                std::to_string(kFormatVersion));
  }
  if (got < kHeaderBytes) return fail(path + ": plane table truncated in its header");
  std::uint64_t stored_header_sum;
  std::memcpy(&stored_header_sum, head + kHeaderBytes - 8, 8);
  if (checksum_bytes(head, kHeaderBytes - 8) != stored_header_sum) {
    return fail(path + ": plane table header is damaged (checksum mismatch)");
  }
  const Header h = decode(head);
  if (h.kind != static_cast<std::uint32_t>(kind)) {
    return fail(path + ": plane table of kind '" +
                (h.kind <= 1 ? table_kind_name(static_cast<TableKind>(h.kind)) : std::string("?")) + "', expected '" +
                table_kind_name(kind) + "'");
  }
  if (h.samples != static_cast<std::uint32_t>(expected.count)) {
    return fail(path + ": plane table built for N = " + std::to_string(h.samples) + " samples, the pattern has " +
                std::to_string(expected.count));
  }
  if (h.resolution != static_cast<std::uint32_t>(resolution)) {
    return fail(path + ": plane table resolution " + std::to_string(h.resolution) + ", expected " +
                std::to_string(resolution));
  }
  if (h.falloff != static_cast<std::uint32_t>(expected.falloff) || h.seed != expected.seed ||
      h.pattern_hash != lut::pattern_hash(expected)) {
    return fail(path + ": plane table built from another sample pattern (falloff, seed or sample hash differ)");
  }
  if (auto ok = check_table_resolution(resolution); !ok) return fail(path + ": " + ok.error().message);
  const std::size_t payload = cube(resolution) * static_cast<std::size_t>(mask_bits_for(expected.count) / 8);
  if (h.bits != static_cast<std::uint32_t>(mask_bits_for(expected.count)) || h.payload_bytes != payload) {
    return fail(path + ": plane table header is inconsistent (mask width or payload size)");
  }

  PlaneTable table;
  table.kind_ = kind;
  table.falloff_ = expected.falloff;
  table.seed_ = expected.seed;
  table.pattern_hash_ = h.pattern_hash;
  table.allocate(expected.count, resolution);
  in.read(static_cast<char*>(table.data()), static_cast<std::streamsize>(payload));
  if (static_cast<std::size_t>(in.gcount()) != payload) {
    return fail(path + ": plane table truncated (" + std::to_string(in.gcount()) + " of " + std::to_string(payload) +
                " payload bytes)");
  }
  if (in.peek() != std::char_traits<char>::eof()) return fail(path + ": plane table has trailing data");
  if (checksum_bytes(static_cast<const unsigned char*>(table.base_), payload) != h.payload_checksum) {
    return fail(path + ": plane table is damaged (payload checksum mismatch)");
  }
  return table;
}

}  // namespace exao::lut
