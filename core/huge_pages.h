#pragma once
// exao::reserve_huge: room for a large array, backed by transparent huge pages where the kernel
// has them. A big scene's arrays are written once, front to back, right after they are
// reserved (the loaders, the BVH's leaves), and with 4 KiB pages the kernel's fault per page
// was a third of loading a binary PLY (perf, docs/scale.md); 2 MiB pages fault 512 times less.
// The kernel may still give 4 KiB pages (THP off, or no huge page free): the same bytes,
// only slower.

#include <cstddef>
#include <vector>

namespace exao {

/// Asks the kernel for huge pages over the whole 2 MiB pages inside [p, p + bytes)
/// (madvise MADV_HUGEPAGE); nothing for less than one. Call before the bytes are first written.
void advise_huge_pages(const void* p, std::size_t bytes);

/// v.reserve(n), then advise_huge_pages over the new storage.
template <class T, class Allocator>
void reserve_huge(std::vector<T, Allocator>& v, std::size_t n) {
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace exao
