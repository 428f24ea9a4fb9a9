#pragma once
// exao::lut::FlushDenormals: flush-to-zero and denormals-are-zero for the current thread, for
// the lifetime of the object (the previous mode is restored).
//
// Why every backend runs its mask work inside one: Embree switches FTZ/DAZ on in the TBB worker
// threads it runs on and never switches it off, so without this a triangle mask whose arithmetic
// meets a denormal (a product of two tiny coordinates) could differ with the thread that happened
// to compute it, and bvh == brute would hold only by luck.

#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#endif

namespace exao::lut {

class FlushDenormals {
 public:
#if defined(__SSE__) || defined(__x86_64__)
  FlushDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero); }
  ~FlushDenormals() { _mm_setcsr(saved_); }
#else
  FlushDenormals() = default;
#endif
  FlushDenormals(const FlushDenormals&) = delete;
  FlushDenormals& operator=(const FlushDenormals&) = delete;

 private:
#if defined(__SSE__) || defined(__x86_64__)
  static constexpr unsigned kFlushToZero = 0x8000;      // MXCSR.FTZ
  static constexpr unsigned kDenormalsAreZero = 0x0040;  // MXCSR.DAZ
  unsigned saved_;
#endif
};

}  // namespace exao::lut
