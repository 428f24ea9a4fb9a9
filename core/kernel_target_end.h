// Closes what core/kernel_target.h opened. No include guard.
#pragma GCC pop_options
#undef EXAO_KERNEL_NS
#undef EXAO_KERNEL_LANES
#undef EXAO_KERNEL_ISA
