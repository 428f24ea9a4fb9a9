#include "ssao/error_stats.h"

#include <cassert>

namespace exao::ssao {

AoError error_stats(std::span<const float> ao, std::span<const float> exact, std::span<const std::uint8_t> valid) {
  assert(ao.size() == exact.size() && ao.size() == valid.size());
  AoError e;
  for (std::size_t p = 0; p < ao.size(); ++p) {
    if (valid[p]) e.add(ao[p], exact[p]);
  }
  return e;
}

}  // namespace exao::ssao
