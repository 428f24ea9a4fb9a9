#pragma once
// exao::lut::PlaneTable: the paper's 3D plane-bitmask look-up table (Sec. 3.1; DESIGN.md
// section 4). R^3 cells; a plane (m, d) (unit normal m away from the origin, distance d in units
// of r) is addressed by
//     c = m * (1 - 7/8 * d) / max(|m.x|, |m.y|, |m.z|)         (each component in [-1, 1])
//     cell_k = clamp(floor((c_k + 1) / 2 * R), 0, R - 1)
// d_norm = 1 - 7/8 d keeps planes near the origin away from the crowded centre, and the division
// by the largest component stretches the sphere of normals to the cube's corners.
//
// What a cell stores: the mask of one plane, evaluated exactly on the pattern:
//   - interior cells: the plane of the cell's centre c, i.e. d_norm = max_k |c_k|, m = c / |c|,
//     d = 8/7 (1 - d_norm);
//   - the outermost shell (any index 0 or R - 1): a plane with d = 0. As the paper says, "the
//     outermost cells correspond to planes with d = 0": every edge plane (d = 0 exactly, so
//     max |c_k| = 1) lands there, making the shell the edge-plane cube map of Kautz et al. Its
//     normal is that of the middle of the cell's patch of the cube's surface (the centre with
//     its outermost coordinates set to +-1), which is where the addresses of the d = 0 planes
//     of the cell are centred; the centre's own normal c / |c| is up to half a cell off that near
//     the cube's edges, and measured 0.01-0.06 points worse agreement with Embree
//     (tests/brute_test.cpp). Triangle planes with d < 16 / (7R) r also land in the shell and
//     are treated as d = 0.
//
// Memory is R^3 * Bits / 8 bytes, Bits = the mask width (N rounded up to a power of two, at least
// 64), so a look-up is one aligned load of a whole Mask<Bits>. Default R per width, all in the
// tens of MiB:
//     Bits   64: R = 128  ->  16 MiB        Bits  512: R = 80  ->  31.25 MiB
//     Bits  128: R = 128  ->  32 MiB        Bits 1024: R = 64  ->  32 MiB
//     Bits  256: R =  96  ->  27 MiB
// (N = 32 pads to 64 bits: half of each 16 MiB row is zero.)
//
// Two kinds: Points tests the sample points s_i = l_i w_i (triangle and edge planes); Directions
// tests the unit directions w_i, for the paper's cone tests of bounding spheres when the ray
// lengths differ (Sec. 5, Fig. 4, right).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include "core/check.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/mask.h"
#include "core/sample_pattern.h"
#include "lut/plane.h"

namespace exao::lut {

enum class TableKind : std::uint32_t { Points = 0, Directions = 1 };

[[nodiscard]] constexpr auto enum_names(TableKind) {
  return std::to_array<EnumName<TableKind>>({{TableKind::Points, "points"}, {TableKind::Directions, "directions"}});
}

[[nodiscard]] const char* table_kind_name(TableKind kind);

/// The default resolution for N samples (see the header comment for the memory).
[[nodiscard]] constexpr int default_table_resolution(int samples) {
  switch (mask_bits_for(samples)) {
    case 64: return 128;
    case 128: return 128;
    case 256: return 96;
    case 512: return 80;
    default: return 64;
  }
}
inline constexpr int kMinTableResolution = 4;    // at least one interior cell per axis pair
inline constexpr int kMaxTableResolution = 256;  // 2 GiB at 1024 bits: beyond that is a typo

/// Checks that R is in [kMinTableResolution, kMaxTableResolution]; the error names the value.
[[nodiscard]] Result<void> check_table_resolution(int resolution);

/// A 64-bit hash of everything that defines a pattern: N, falloff, seed and the bits of every
/// direction and length float. Two patterns with equal hashes cast the same rays.
[[nodiscard]] std::uint64_t pattern_hash(const SamplePattern& pattern);

class PlaneTable {
 public:
  PlaneTable() = default;

  /// Builds the table for `pattern` at resolution R (0: default_table_resolution(N)), on all
  /// TBB threads. Fails only on a bad R. About 0.1 s at the default sizes on 2 cores.
  [[nodiscard]] static Result<PlaneTable> build(const SamplePattern& pattern, TableKind kind, int resolution = 0);

  /// Writes the table (binary: a header that pins the format version, N, R, the mask width, the
  /// kind, the pattern's falloff, seed and hash, the payload's size and checksum, and the header's
  /// own checksum; then the R^3 masks). Atomic: a temporary file, then a rename.
  [[nodiscard]] Result<void> save(const std::string& path) const;

  /// Reads a table saved by save() and checks it against what the caller is about to use: the
  /// pattern (N, falloff, seed, hash), the kind and R (0: default for N). A file that is not a
  /// table, of another format version, for another pattern, kind or R, truncated, or damaged
  /// (checksum) is refused with a one-line error that names the file.
  [[nodiscard]] static Result<PlaneTable> load(const std::string& path, const SamplePattern& expected, TableKind kind,
                                               int resolution = 0);

  [[nodiscard]] int resolution() const { return resolution_; }   // R
  [[nodiscard]] int samples() const { return samples_; }         // N
  [[nodiscard]] int bits() const { return bits_; }               // mask width
  [[nodiscard]] TableKind kind() const { return kind_; }
  [[nodiscard]] std::uint64_t pattern_hash() const { return pattern_hash_; }
  [[nodiscard]] std::size_t cell_count() const { return cells_; }
  /// Bytes of masks: R^3 * bits / 8.
  [[nodiscard]] std::size_t memory_bytes() const { return cells_ * static_cast<std::size_t>(bits_ / 8); }

  /// The cell of plane (m_unit, d_over_r), by the address above. m_unit: finite, non-zero, unit
  /// length when d_over_r > 0 (for d = 0 only its direction matters: any length will do);
  /// d_over_r in [0, 1] (values outside are clamped to the cube).
  [[nodiscard]] std::size_t cell_index(const glm::vec3& m_unit, float d_over_r) const {
    const float largest = std::max(std::abs(m_unit.x), std::max(std::abs(m_unit.y), std::abs(m_unit.z)));
    const float scale = (1.0f - 0.875f * d_over_r) / largest;
    const float half_r = 0.5f * static_cast<float>(resolution_);
    const float top = static_cast<float>(resolution_ - 1);
    // fmax/fmin also send a NaN to the cube's corner rather than into undefined behaviour.
    const auto axis = [&](float ck) {
      return static_cast<std::size_t>(std::fmin(std::fmax((ck * scale + 1.0f) * half_r, 0.0f), top));
    };
    const std::size_t r = static_cast<std::size_t>(resolution_);
    return (axis(m_unit.z) * r + axis(m_unit.y)) * r + axis(m_unit.x);
  }

  /// The plane whose mask cell `index` stores (see the header comment), normalised units.
  [[nodiscard]] Plane cell_plane(std::size_t index) const;

  /// True for the cells of the outermost shell (the d = 0 planes).
  [[nodiscard]] bool in_outer_shell(std::size_t index) const;

  /// The mask stored in a cell. Bits must equal bits().
  template <int Bits>
  [[nodiscard]] const Mask<Bits>& cell(std::size_t index) const {
    EXAO_DCHECK_EQ(Bits, bits_);  // the hot loop of every mask: Debug builds only
    EXAO_DCHECK_LT(index, cells_);
    return static_cast<const Mask<Bits>*>(base_)[index];
  }

  /// The mask of the cell of plane (m_unit, d_over_r): one aligned load.
  template <int Bits>
  [[nodiscard]] const Mask<Bits>& lookup(const glm::vec3& m_unit, float d_over_r) const {
    return cell<Bits>(cell_index(m_unit, d_over_r));
  }

  PlaneTable(PlaneTable&& other) noexcept { *this = std::move(other); }
  PlaneTable& operator=(PlaneTable&& other) noexcept;
  PlaneTable(const PlaneTable&) = delete;
  PlaneTable& operator=(const PlaneTable&) = delete;

 private:
  using Storage = std::variant<std::monostate, std::vector<Mask<64>>, std::vector<Mask<128>>, std::vector<Mask<256>>,
                               std::vector<Mask<512>>, std::vector<Mask<1024>>>;

  // Allocates R^3 zero masks of the width for N and points base_ at them.
  void allocate(int samples, int resolution);
  [[nodiscard]] void* data();

  int samples_ = 0;
  int resolution_ = 0;
  int bits_ = 0;
  TableKind kind_ = TableKind::Points;
  Falloff falloff_ = Falloff::Constant;
  std::uint64_t seed_ = 0;
  std::uint64_t pattern_hash_ = 0;
  std::size_t cells_ = 0;
  Storage storage_;
  const void* base_ = nullptr;  // the masks of storage_, for a look-up without a variant visit
};

}  // namespace exao::lut
