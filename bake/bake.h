#pragma once
// exao::bake::bake: AO baked into a glTF model, per vertex or per texel. The AO comes from the
// library engine (engine/engine.h, any method that serves points), so the bake only decides where
// the receivers are and where their values go.

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bake/document.h"
#include "bake/options.h"
#include "bake/result.h"
#include "core/error.h"
#include "engine/engine.h"
#include "core/progress.h"
#include "core/receiver_frame.h"

namespace exao::bake {

/// Bakes: finds the receivers, asks `engine` about them (progress in receivers), and writes the
/// result into the document's
/// model (vertex: a COLOR_0 or _AO accessor per primitive, meshes split per node where their AO
/// differs; texture: maps, and each material's occlusionTexture with texCoord = the set laid out
/// by and the KHR_texture_transform it was seen through, its other textures kept; primitives on
/// generated UVs get their vertices split along chart seams and the new set). `engine` must be
/// built from document.scene() for Receivers::Points. Fails, naming the problem, on bad options
/// (naming the field: "texel_samples: ..."), or with UvMode::File a primitive without the UV set
/// (the message suggests a vertex bake) or UVs outside [0, 1].
[[nodiscard]] Result<BakeResult> bake(Document& document, const BakeOptions& options, const engine::Engine& engine,
                                      const ProgressCallback& progress = {});
/// bake() with the engine's per-call settings: exao merge supplies every receiver's count from
/// the parts of a sharded bake (engine::RunOptions::supplied_blocked), so that the atlas, the
/// dilation and the files are made once, from the complete answers, exactly as one run makes them.
[[nodiscard]] Result<BakeResult> bake(Document& document, const BakeOptions& options, const engine::Engine& engine,
                                      const engine::RunOptions& run);

/// The receivers bake() would ask the engine about, in its order, without computing AO or
/// changing the document (exao bench --receivers times methods on them). Fails as bake() does.
[[nodiscard]] Result<std::vector<Receiver>> bake_receivers(Document& document, const BakeOptions& options);

}  // namespace exao::bake
