#pragma once
// exao::DefaultInitAllocator: an allocator whose resize(n) leaves new elements of a trivial type
// unwritten, for large arrays that a parallel loop fills right after. std::vector's resize writes
// zeros first, one thread over the whole array: for the BVH's leaves (half a gigabyte at 8M
// triangles) that was a serial pass, and the page faults all landed on one core.

#include <memory>
#include <new>
#include <type_traits>
#include <utility>

namespace exao {

template <class T, class Base = std::allocator<T>>
class DefaultInitAllocator : public Base {
 public:
  using value_type = T;
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U, typename std::allocator_traits<Base>::template rebind_alloc<U>>;
  };

  DefaultInitAllocator() = default;
  template <class U, class B>
  DefaultInitAllocator(const DefaultInitAllocator<U, B>& other) : Base(other) {}  // NOLINT: rebinding must be implicit

  // Value-initialisation (resize, the one-argument constructor) becomes default-initialisation.
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    std::allocator_traits<Base>::construct(static_cast<Base&>(*this), p, std::forward<Args>(args)...);
  }
  friend bool operator==(const DefaultInitAllocator&, const DefaultInitAllocator&) { return true; }  // stateless
};

}  // namespace exao
