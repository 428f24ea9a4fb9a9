// AFL++ target: the polygon-soup formats (OBJ, PLY, OFF, STL, through CGAL and exao's
// pre-scans), chosen by the extension of the file each argument names; scripts/fuzz.sh runs one
// campaign per format (afl-fuzz -e obj, ...). `exao_fuzz_soup FILE...` replays inputs by hand.

#include "io/load_scene.h"
#include "tests/fuzz/fuzz_check.h"

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string path = argv[i];
    exao::fuzz::check_scene(exao::load_polygon_soup(path), path);
  }
  return 0;
}
