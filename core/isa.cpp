#include "core/isa.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace exao {
namespace {

constexpr std::array kAll = all_values<Isa>();

bool cpu_runs(Isa isa) {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  switch (isa) {
    case Isa::Scalar: return true;
    case Isa::Sse2: return __builtin_cpu_supports("sse2");
    case Isa::Sse4: return __builtin_cpu_supports("sse4.2") && __builtin_cpu_supports("popcnt");
    case Isa::Avx2:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") &&
             __builtin_cpu_supports("popcnt");
    case Isa::Avx512:
      return cpu_runs(Isa::Avx2) && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq");
  }
  return false;
#else
  return isa == Isa::Scalar;
#endif
}

}  // namespace

const char* isa_name(Isa isa) { return name_of(isa); }

Result<std::optional<Isa>> parse_isa(std::string_view name) {
  if (name == "auto") return std::optional<Isa>{};
  if (const std::optional<Isa> isa = parse_enum<Isa>(name)) return isa;
  return fail("isa: '" + std::string(name) + "' is not an instruction set (auto, " + name_list<Isa>() + ")");
}

int isa_lanes(Isa isa) {
  switch (isa) {
    case Isa::Scalar: return 1;
    case Isa::Sse2:
    case Isa::Sse4: return 4;
    case Isa::Avx2: return 8;
    case Isa::Avx512: return 16;
  }
  return 1;
}

bool isa_supported(Isa isa) {
  static const std::array<bool, kAll.size()> runs = [] {
    std::array<bool, kAll.size()> r{};
    for (std::size_t i = 0; i < kAll.size(); ++i) r[i] = cpu_runs(kAll[i]);
    return r;
  }();
  return runs[static_cast<std::size_t>(isa)];
}

std::span<const Isa> supported_isas() {
  static const std::vector<Isa> levels = [] {
    std::vector<Isa> v;
    for (const Isa isa : kAll) {
      if (isa_supported(isa)) v.push_back(isa);
    }
    return v;
  }();
  return levels;
}

Result<std::optional<Isa>> environment_isa() {
  const char* env = std::getenv("EXAO_ISA");
  if (!env || !*env) return std::optional<Isa>{};
  const Result<std::optional<Isa>> parsed = parse_isa(env);
  if (!parsed) {
    return fail(std::string("EXAO_ISA: '") + env +
                "' is not an instruction set (scalar, sse2, sse4, avx2, avx512 or auto)");
  }
  if (*parsed && !isa_supported(**parsed)) {
    return fail(std::string("EXAO_ISA: this CPU does not run ") + env + " (it runs up to " +
                isa_name(supported_isas().back()) + ")");
  }
  return *parsed;
}

Isa default_isa() {
  static const Isa chosen = [] {
#if defined(EXAO_FORCE_SCALAR)
    const Isa best = Isa::Scalar;  // the build option EXAO_FORCE_SCALAR
#else
    const Isa best = supported_isas().back();
#endif
    // A bad EXAO_ISA is refused by resolve_isa, where an engine is built; here, silently, the
    // best level (the library never prints).
    const Result<std::optional<Isa>> env = environment_isa();
    return env && *env ? **env : best;
  }();
  return chosen;
}

Result<Isa> resolve_isa(std::optional<Isa> requested) {
  if (!requested) {
    if (auto env = environment_isa(); !env) return std::unexpected(env.error());
    return default_isa();
  }
  if (!isa_supported(*requested)) {
    return fail(std::string("isa: this CPU does not run ") + isa_name(*requested) + " (it runs up to " +
                isa_name(supported_isas().back()) + ")");
  }
  return *requested;
}

}  // namespace exao
