// Allocator for large, short-lived working arrays (max-flow networks): requests of 2 MiB or more
// are 2 MiB-aligned and marked MADV_HUGEPAGE (Linux), so first touching them costs one page fault
// per 2 MiB instead of one per 4 KiB. On the VMs this project runs on a 4 KiB first-touch fault
// costs ~11 us, so the ~45 MB network of a 100k-node cut spent ~0.15 s in page faults per cut
// pursuit call (measured; docs/solvers.md "memory"). Smaller requests use operator new unchanged.
// Without transparent huge pages (THP "never") the advice is ignored and nothing else changes.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <new>

#include <omp.h>

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
    if (!advise) FirstTouchInParallel(static_cast<char*>(p), rounded);
    return static_cast<T*>(p);
  }

  // Ordinary 4 KiB pages of a big block are faulted in by all threads at once, outside a parallel
  // region: the caller (bk's network build) then fills them on one thread, and each first-touch
  // fault costs ~10 us on these VMs (the host backs guest memory lazily), 0.3 s for the 3M scene's
  // 128 MB of arcs on one thread (docs/solvers.md "cp speed (4)"). Inside a parallel region (cp's
  // per-thread networks) each thread already touches its own.
  static void FirstTouchInParallel(char* p, std::size_t bytes) {
    constexpr std::size_t kPage = 4096, kMinBytes = std::size_t{8} << 20;
    if (bytes < kMinBytes || omp_in_parallel()) return;
    const auto pages = static_cast<std::int64_t>(bytes / kPage);
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < pages; ++k) p[std::size_t(k) * kPage] = 0;
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
