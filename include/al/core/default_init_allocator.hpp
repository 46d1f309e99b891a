// Allocator whose value-less construction default-initialises: `resize(n)` of a vector of
// arithmetic T leaves the new elements unwritten instead of zeroing them on the calling thread.
// For big working arrays that a parallel loop fills right after: on this project's VMs the first
// touch of a fresh 4 KiB page costs 1-10 us (the host backs guest memory lazily), so a serial
// zero-fill of 96 MB took 0.24 s before the fill loop wrote it again (level-set partition at 3M,
// docs/solvers.md "Memory and first touch at 3M"); left to the loop, both threads share the
// first touch.
#pragma once
#include <memory>
#include <new>
#include <type_traits>
#include <utility>

namespace al {

template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() noexcept = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}  // NOLINT: allocator rebinding

  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T, class U>
bool operator==(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept { return true; }

}  // namespace al
