#include "lut/mask_kernels.h"

#include <cstdio>
#include <cstdlib>

namespace exao::lut {

const MaskKernels& mask_kernels(Isa isa) {
  if (!isa_supported(isa)) {
    // A programmer's error: MaskEngine resolves the level against the CPU before it gets here.
    std::fprintf(stderr, "exao: internal error: mask kernels for %s requested on a CPU without it\n", isa_name(isa));
    std::abort();
  }
  switch (isa) {
    case Isa::Scalar: return scalar_lanes::kernels();
    case Isa::Sse2: return sse2::kernels();
    case Isa::Sse4: return sse4::kernels();
    case Isa::Avx2: return avx2::kernels();
    case Isa::Avx512: return avx512::kernels();
  }
  return scalar_lanes::kernels();
}

}  // namespace exao::lut
