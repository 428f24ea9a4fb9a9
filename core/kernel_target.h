// The instruction set of a kernel translation unit. A file compiled once per level of
// core/isa.h (CMake's exao_kernel_objects) includes every header it needs first, then this file,
// which opens `#pragma GCC target` for the level named by EXAO_KERNEL_ISA_<LEVEL> and defines
// EXAO_KERNEL_NS (the namespace that keeps each level's symbols apart) and EXAO_KERNEL_LANES,
// then its own -inl.h kernels inside namespace EXAO_KERNEL_NS, then core/kernel_target_end.h.
//
// Why a pragma and not -mavx2 on the file: inline functions of the headers included before
// (the standard library, GLM, exao's own) keep the baseline instruction set in their
// out-of-line copies, so the linker can never pick an AVX copy for code that runs on any CPU;
// inside the kernels they are inlined and compiled for the level. No FMA is enabled, so every
// level rounds the same way.
//
// No include guard: one inclusion per translation unit.

#if defined(EXAO_KERNEL_ISA_AVX512)
#pragma GCC push_options
#pragma GCC target("avx512f,avx512bw,avx512vl,avx512dq,avx2,bmi,bmi2,lzcnt,popcnt")
#define EXAO_KERNEL_NS avx512
#define EXAO_KERNEL_LANES 16
#define EXAO_KERNEL_ISA ::exao::Isa::Avx512
#elif defined(EXAO_KERNEL_ISA_AVX2)
#pragma GCC push_options
#pragma GCC target("avx2,bmi,bmi2,lzcnt,popcnt")
#define EXAO_KERNEL_NS avx2
#define EXAO_KERNEL_LANES 8
#define EXAO_KERNEL_ISA ::exao::Isa::Avx2
#elif defined(EXAO_KERNEL_ISA_SSE4)
#pragma GCC push_options
#pragma GCC target("sse4.2,popcnt")
#define EXAO_KERNEL_NS sse4
#define EXAO_KERNEL_LANES 4
#define EXAO_KERNEL_ISA ::exao::Isa::Sse4
#elif defined(EXAO_KERNEL_ISA_SSE2)
#pragma GCC push_options
#define EXAO_KERNEL_NS sse2
#define EXAO_KERNEL_LANES 4
#define EXAO_KERNEL_ISA ::exao::Isa::Sse2
#elif defined(EXAO_KERNEL_ISA_SCALAR)
#pragma GCC push_options
#define EXAO_KERNEL_NS scalar_lanes
#define EXAO_KERNEL_LANES 1
#define EXAO_KERNEL_ISA ::exao::Isa::Scalar
#else
#error "a kernel translation unit needs EXAO_KERNEL_ISA_<LEVEL> (see exao_kernel_objects in CMake)"
#endif
