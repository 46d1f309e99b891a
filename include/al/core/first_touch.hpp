// Big working arrays whose pages are faulted in by all threads before a serial fill writes them.
// On this project's VMs the first touch of a fresh 4 KiB page costs ~2-10 us (the host backs guest
// memory lazily), so a serial resize or assign of tens of MB costs tens of milliseconds of
// page faults on one thread while the other core waits (docs/benchmarks.md "Scale").
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include <omp.h>

namespace al {

// Reserves room for n elements of v and touches one byte of every page of the new storage from
// all threads (the storage is raw memory until resize/assign constructs the elements in it).
// Small arrays, and calls inside a parallel region, only reserve.
template <class T, class A>
void ReserveFirstTouched(std::vector<T, A>& v, std::size_t n) {
  constexpr std::size_t kPage = 4096, kMinBytes = std::size_t{8} << 20;
  if (v.capacity() >= n) return;
  v.reserve(n);
  const std::size_t bytes = (v.capacity() - v.size()) * sizeof(T);
  if (bytes < kMinBytes || omp_in_parallel()) return;
  unsigned char* storage = reinterpret_cast<unsigned char*>(v.data() + v.size());
  const auto pages = static_cast<std::int64_t>(bytes / kPage);
#pragma omp parallel for schedule(static)
  for (std::int64_t k = 0; k < pages; ++k) storage[std::size_t(k) * kPage] = 0;
}

}  // namespace al
