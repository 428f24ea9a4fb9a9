#include "cli/option_flags.h"

#include <array>
#include <cstdio>

#include "cli/program.h"

namespace exao::cli {
namespace {

constexpr std::array<std::pair<std::string_view, std::string_view>, 31> kFlags{{
    // engine::Options
    {"radius", "--radius"},
    {"samples", "--samples"},
    {"falloff", "--falloff"},
    {"origin_offset", "--offset"},
    {"sidedness", "--sided"},
    {"cutouts", "--cutouts"},
    {"blend", "--blend"},
    {"blend_cutoff", "--blend"},
    {"method", "--method"},
    {"masks", "--masks"},
    {"hybrid", "--hybrid"},
    {"threads", "--threads"},
    {"table_resolution", "--table-resolution"},
    {"bvh.branching", "--branching"},
    {"bvh.max_leaf_size", "--leaf-size"},
    {"raster.alpha", "--alpha"},
    {"embree.rays", "--embree-rays"},
    {"embree.across_receivers", "--embree-per-receiver"},
    {"isa", "--isa"},
    {"lod", "--lod"},
    {"lod_eps1", "--lod"},
    {"lod_levels", "--lod-levels"},
    {"lod_k", "--lod-k"},
    {"lod_overlap", "--lod-overlap"},
    {"lod_filter", "--lod-filter"},
    // bake::BakeOptions
    {"texture_size", "--texture"},
    {"texel_samples", "--texel-samples"},
    {"margin", "--margin"},
    {"uv_set", "--uv-set"},
    {"normals", "--normals"},
    {"png_bits", "--png-bits"},
}};

}  // namespace

std::string with_flags(const std::string& message, const FlagOverrides& overrides) {
  const std::size_t colon = message.find(':');
  if (colon == std::string::npos) return message;
  const std::string_view head = std::string_view(message).substr(0, colon);
  for (const auto& [option, flag] : overrides) {
    if (head == option) return std::string(flag) + message.substr(colon);
  }
  for (const auto& [option, flag] : kFlags) {
    if (head == option) return std::string(flag) + message.substr(colon);
  }
  return message;
}

int report(const Error& error, const FlagOverrides& overrides) {
  const std::string line = with_flags(error.message, overrides);
  if (const Embedding* e = embedding(); e && e->error) {
    e->error(line);  // the embedding shows it (the Python module raises it)
    return 1;
  }
  std::fprintf(stderr, "exao: %s\n", line.c_str());
  return 1;
}

}  // namespace exao::cli
