// Big working arrays whose pages are faulted in by all threads before a serial fill writes them.
// On this project's VMs the first touch of a fresh 4 KiB page costs 1-10 us (the host backs guest
// memory lazily), so a serial resize or assign of tens of MB costs tens of milliseconds of
// page faults on one thread while the other core waits (docs/solvers.md "Memory and first touch
// at 3M").
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include <omp.h>

namespace al {

// Writes one byte of every 4 KiB page of the raw storage [p, p + bytes) from all threads, so its
// page faults are shared. Blocks under 8 MiB, and calls inside a parallel region (where each
// thread already touches its own), are left alone. The pages go out in runs of 64: a block that
// reuses freed heap at its start and grows the heap at its end has all its faults at the end,
// which halves by address gave to one thread (3M room scene: that thread faulted for 0.1 s while
// the other waited).
inline void FirstTouchPages(void* p, std::size_t bytes) {
  constexpr std::size_t kPage = 4096, kMinBytes = std::size_t{8} << 20;
  if (bytes < kMinBytes || omp_in_parallel()) return;
  unsigned char* storage = static_cast<unsigned char*>(p);
  const auto pages = static_cast<std::int64_t>(bytes / kPage);
#pragma omp parallel for schedule(dynamic, 64)
  for (std::int64_t k = 0; k < pages; ++k) storage[std::size_t(k) * kPage] = 0;
}

// The storage of a row-major matrix first-touched by all threads before a loop fills it.
template <class Matrix>
void FirstTouchMatrix(Matrix& m) {
  FirstTouchPages(m.data(), std::size_t(m.size()) * sizeof(typename Matrix::Scalar));
}

// Reserves room for n elements of v and first-touches the new storage (FirstTouchPages; it is raw
// memory until resize/assign constructs the elements in it).
template <class T, class A>
void ReserveFirstTouched(std::vector<T, A>& v, std::size_t n) {
  if (v.capacity() >= n) return;
  v.reserve(n);
  FirstTouchPages(v.data() + v.size(), (v.capacity() - v.size()) * sizeof(T));
}

}  // namespace al
