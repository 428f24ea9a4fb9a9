#pragma once
// What a Document holds. Internal to exao_bake: it exposes tinygltf.

#include <tiny_gltf.h>

#include <cstdint>
#include <string>
#include <vector>

#include "bake/document.h"
#include "bake/model_walk.h"

namespace exao::bake {

struct Document::Impl {
  tinygltf::Model model;
  ModelWalk walk;                  // of the model as read: the bake adds to the model, never moves it
  std::string name;
  std::string source_path;         // the glTF read; empty when converted
  bool from_gltf = false;
  bool embedded_buffers = false;   // every buffer of the input was a data: URI
  std::vector<std::string> input_files;
  std::vector<std::string> notes;
  /// Per image: the encoded bytes as read (external file, data: URI or GLB buffer view), empty
  /// when the file was missing; and the folder external URIs are relative to.
  std::vector<std::vector<std::uint8_t>> image_bytes;
  std::string base_folder;
};

}  // namespace exao::bake
