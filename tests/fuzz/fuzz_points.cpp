// AFL++ target: the receiver reader of `exao query --points`, text or PLY by the extension of
// the file each argument names (scripts/fuzz.sh: afl-fuzz -e txt, -e ply). Every receiver it
// returns must be finite, within the coordinate limit, with a non-zero normal.

#include <cmath>
#include <cstdlib>

#include "io/receiver_io.h"
#include "tests/fuzz/fuzz_check.h"

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string path = argv[i];
    const exao::Result<std::vector<exao::Receiver>> receivers = exao::load_receivers(path);
    if (!receivers) {
      exao::fuzz::check_error(receivers.error(), path);
      continue;
    }
    for (const exao::Receiver& r : *receivers) {
      const glm::vec3& n = r.normal;
      const bool finite_normal = std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z);
      if (!exao::within_coordinate_limit(r.position) || !finite_normal || n == glm::vec3(0.0f)) {
        std::abort();
      }
    }
  }
  return 0;
}
