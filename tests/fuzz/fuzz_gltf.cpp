// AFL++ target: the glTF and GLB readers, core's scene loader and the bake's document (both read
// through io/gltf_file.h, then walk the model their own way), on the file each argument names;
// GLB is told by its magic, so one target covers both. scripts/fuzz.sh runs it; `exao_fuzz_gltf FILE...` replays inputs by hand.

#include "bake/document.h"
#include "io/load_scene.h"
#include "tests/fuzz/fuzz_check.h"

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string path = argv[i];
    exao::fuzz::check_scene(exao::load_gltf(path), path);
    const exao::Result<exao::bake::Document> document = exao::bake::Document::open(path);
    if (!document) exao::fuzz::check_error(document.error(), path);
  }
  return 0;
}
