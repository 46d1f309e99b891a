// Allocator for large, short-lived working arrays (max-flow networks): requests of 2 MiB or more
// are 2 MiB-aligned and marked MADV_HUGEPAGE (Linux), so first touching them costs one page fault
// per 2 MiB instead of one per 4 KiB. On the VMs this project runs on a 4 KiB first-touch fault
// costs ~11 us, so the ~45 MB network of a 100k-node cut spent ~0.15 s in page faults per cut
// pursuit call (measured; docs/solvers.md "memory"). Smaller requests use operator new unchanged.
// Without transparent huge pages (THP "never") the advice is ignored and nothing else changes.
#pragma once
#include <cstddef>
#include <cstdlib>
#include <limits>
#include <new>

#include "al/core/first_touch.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace al {

template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t kHugePage = std::size_t{2} << 20;

  // advise = false: the same alignment and release, without the huge-page advice (for buffers
  // touched once, where waiting for the kernel to assemble huge pages costs more than it saves).
  bool advise = true;

  HugePageAllocator() noexcept = default;
  explicit HugePageAllocator(bool advise_huge_pages) noexcept : advise(advise_huge_pages) {}
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>& other) noexcept : advise(other.advise) {}

  T* allocate(std::size_t n) {
    // Also after rounding up to whole huge pages the size must be a valid object size.
    constexpr std::size_t kMaxBytes =
        static_cast<std::size_t>(std::numeric_limits<std::ptrdiff_t>::max()) - kHugePage;
    if (n > kMaxBytes / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugePage) return static_cast<T*>(::operator new(bytes));
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (p == nullptr) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (advise) madvise(p, rounded, MADV_HUGEPAGE);  // advice only: failure leaves ordinary pages
#endif
    // Without the advice, ordinary pages: faulted in by all threads (first_touch.hpp), since the
    // caller (bk's network build) then fills them on one thread: 128 MB of arcs at 3M.
    if (!advise) FirstTouchPages(p, rounded);
    return static_cast<T*>(p);
  }

  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kHugePage) ::operator delete(p);
    else std::free(p);
  }

  // Any instance frees what another allocated (the advice changes nothing there).
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
};

}  // namespace al
