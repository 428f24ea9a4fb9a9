#pragma once
// exao::Isa: the instruction sets exao's hot kernels (masks, sphere and node tests, traversal)
// are compiled for, all in one build, and the run-time choice among them (the way Embree picks
// its kernels). Every level computes the same bits: the kernels evaluate the same expression
// tree with separate IEEE multiplies and adds, no FMA (tests/isa_equality_test.cpp
// runs the equality tests on every level the machine has).
//
//   scalar  one float lane, no intrinsics: the twin the vector kernels are checked against;
//   sse2    4 lanes, what every x86-64 has;
//   sse4    4 lanes with SSE4.2 and POPCNT (x86-64-v2);
//   avx2    8 lanes with AVX2, BMI1/2, LZCNT and POPCNT (x86-64-v3 without FMA);
//   avx512  16 lanes with AVX-512 F/BW/VL/DQ (and VPOPCNTDQ for masks of 512 bits and more).

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "core/enum_names.h"
#include "core/error.h"

namespace exao {

enum class Isa { Scalar, Sse2, Sse4, Avx2, Avx512 };

[[nodiscard]] constexpr auto enum_names(Isa) {
  return std::to_array<EnumName<Isa>>(
      {{Isa::Scalar, "scalar"}, {Isa::Sse2, "sse2"}, {Isa::Sse4, "sse4"}, {Isa::Avx2, "avx2"}, {Isa::Avx512, "avx512"}});
}

[[nodiscard]] const char* isa_name(Isa isa);
/// "scalar", "sse2", "sse4", "avx2", "avx512", or "auto" (nullopt: the best this CPU runs).
/// The error names the option `isa` and the value.
[[nodiscard]] Result<std::optional<Isa>> parse_isa(std::string_view name);

/// Float lanes per vector at `isa`: 1, 4, 4, 8, 16.
[[nodiscard]] int isa_lanes(Isa isa);

/// True when this CPU runs the kernels of `isa` (cpuid, once).
[[nodiscard]] bool isa_supported(Isa isa);

/// Every level this CPU runs, from scalar up: the levels the equality tests cover.
[[nodiscard]] std::span<const Isa> supported_isas();

/// What the environment variable EXAO_ISA asks for: nullopt when it is unset, empty or "auto";
/// an error starting "EXAO_ISA: " and giving the value when it names no level, or one this CPU
/// does not run.
[[nodiscard]] Result<std::optional<Isa>> environment_isa();

/// The level an engine uses when its options leave it open: EXAO_ISA when it names a level this
/// CPU runs, else the best level this CPU runs. Never prints: resolve_isa refuses a bad EXAO_ISA.
[[nodiscard]] Isa default_isa();

/// `requested` if the CPU runs it, else an error naming the option `isa`; nullopt: default_isa(),
/// or environment_isa()'s error when EXAO_ISA is set to something this CPU cannot run.
[[nodiscard]] Result<Isa> resolve_isa(std::optional<Isa> requested);

}  // namespace exao
