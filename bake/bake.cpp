#include "bake/bake.h"

#include <chrono>
#include <cstdint>
#include <utility>

#include "bake/corner_normals.h"
#include "bake/document_impl.h"
#include "bake/part_geometry.h"
#include "bake/texture_steps.h"
#include "bake/vertex_output.h"

namespace exao::bake {
namespace {

// The receivers' AO from the engine (which batches, orders and threads them), timed.
Result<void> compute(BakeResult& result, const engine::Engine& engine, const engine::RunOptions& run) {
  const auto start = std::chrono::steady_clock::now();
  Result<std::vector<float>> values = engine.ao(result.receivers, run);
  if (!values) return std::unexpected(values.error());
  result.ao = std::move(*values);
  result.ao_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {};
}

// `engine` null: only the receivers (bake_receivers).
Result<BakeResult> bake_vertices(Document& document, const BakeOptions& options, const engine::Engine* engine,
                                 const engine::RunOptions& run) {
  Document::Impl& doc = document.impl();
  const ModelWalk& walk = doc.walk;
  BakeResult result;
  result.target = Target::Vertex;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> where;  // per receiver: part, vertex
  std::size_t without_file_normals = 0;
  for (std::size_t p = 0; p < walk.parts.size(); ++p) {
    const std::vector<glm::vec3>& world = walk.parts[p].world;
    const bool two_sided = walk.primitives[static_cast<std::size_t>(walk.parts[p].primitive)].two_sided;
    std::vector<glm::vec3> normals = vertex_normals(world, part_corners(walk, p), two_sided);
    if (options.normals == NormalSource::File) {
      auto from_file = file_normals(doc.model, walk, p);
      if (!from_file) return std::unexpected(from_file.error());
      if (from_file->empty()) {
        ++without_file_normals;
      } else {
        // A vertex no triangle uses stays without a receiver; a broken file normal falls back.
        for (std::size_t v = 0; v < normals.size(); ++v) {
          if (normals[v] != glm::vec3(0.0f) && (*from_file)[v] != glm::vec3(0.0f)) normals[v] = (*from_file)[v];
        }
      }
    }
    for (std::size_t v = 0; v < world.size(); ++v) {
      if (normals[v] == glm::vec3(0.0f)) continue;  // no triangle with area uses it: nothing to receive
      result.receivers.push_back({world[v], normals[v], static_cast<std::uint64_t>(result.receivers.size())});
      where.emplace_back(static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(v));
    }
  }
  if (without_file_normals > 0) {
    result.notes.push_back(std::to_string(without_file_normals) +
                           " primitive(s) have no NORMAL: their receivers use geometric normals");
  }
  if (engine == nullptr) return result;
  if (auto ok = compute(result, *engine, run); !ok) return std::unexpected(ok.error());
  result.part_vertex_ao.resize(walk.parts.size());
  for (std::size_t p = 0; p < walk.parts.size(); ++p) result.part_vertex_ao[p].assign(walk.parts[p].world.size(), 1.0f);
  for (std::size_t r = 0; r < where.size(); ++r) result.part_vertex_ao[where[r].first][where[r].second] = result.ao[r];
  auto split = write_vertex_ao(doc.model, walk, result.part_vertex_ao, options.channel, result.notes);
  if (!split) return std::unexpected(split.error());
  result.meshes_split = *split;
  return result;
}

// `engine` null: only the receivers (bake_receivers), the document left as it was. The steps are
// those of bake/texture_steps.h.
Result<BakeResult> bake_texture(Document& document, const BakeOptions& options, const engine::Engine* engine,
                                const engine::RunOptions& run) {
  Document::Impl& doc = document.impl();
  tinygltf::Model& model = doc.model;
  const ModelWalk& walk = doc.walk;
  BakeResult result;
  result.target = Target::Texture;
  TexturePlan plan;
  if (auto ok = choose_uvs(model, walk, options, plan); !ok) return std::unexpected(ok.error());
  assign_maps(walk, options, plan, result);
  if (auto ok = generate_atlases(model, walk, options, plan, result); !ok) return std::unexpected(ok.error());
  note_uv_choices(model, walk, plan, result);
  part_uvs(walk, plan, result);
  if (auto ok = texel_receivers_of(model, walk, options, plan, result); !ok) return std::unexpected(ok.error());
  if (engine == nullptr) return result;
  if (auto ok = compute(result, *engine, run); !ok) return std::unexpected(ok.error());
  fill_maps(model, walk, options, plan, result);
  if (auto ok = write_maps(model, doc.name, walk, options, plan, result); !ok) return std::unexpected(ok.error());
  return result;
}

Result<BakeResult> run_bake(Document& document, const BakeOptions& options, const engine::Engine* engine,
                            const engine::RunOptions& run) {
  if (auto ok = check_options(options); !ok) return std::unexpected(ok.error());
  Result<BakeResult> result = options.target == Target::Vertex ? bake_vertices(document, options, engine, run)
                                                               : bake_texture(document, options, engine, run);
  // What fails past the options is about the input: the message names it.
  if (!result) return fail((document.from_gltf() ? document.impl().source_path : document.name()) + ": " + result.error().message);
  return result;
}

}  // namespace

Result<BakeResult> bake(Document& document, const BakeOptions& options, const engine::Engine& engine,
                        const ProgressCallback& progress) {
  engine::RunOptions run;
  run.progress = progress;
  return run_bake(document, options, &engine, run);
}

Result<BakeResult> bake(Document& document, const BakeOptions& options, const engine::Engine& engine,
                        const engine::RunOptions& run) {
  return run_bake(document, options, &engine, run);
}

Result<std::vector<Receiver>> bake_receivers(Document& document, const BakeOptions& options) {
  Result<BakeResult> result = run_bake(document, options, nullptr, {});
  if (!result) return std::unexpected(result.error());
  return std::move(result->receivers);
}

}  // namespace exao::bake
