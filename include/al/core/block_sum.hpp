// A sum of two terms over [0, n) on all threads that is still the same double for any thread
// count: fixed blocks of indices, each summed in index order, then the blocks added in order.
// For reported sums (objectives); the digits differ from one serial pass, not between runs.
#pragma once
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace al {

// term(i, a, b) adds index i's two terms to a and b; returns (Σ a) + (Σ b).
template <class Term>
double BlockSum2(std::int64_t n, const Term& term) {
  constexpr std::int64_t kBlock = std::int64_t{1} << 14;
  const std::int64_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::pair<double, double>> part(static_cast<std::size_t>(blocks));
#pragma omp parallel for schedule(static) if (blocks > 1)
  for (std::int64_t b = 0; b < blocks; ++b) {
    double a = 0.0, c = 0.0;
    for (std::int64_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) term(i, a, c);
    part[static_cast<std::size_t>(b)] = {a, c};
  }
  double a = 0.0, c = 0.0;
  for (const auto& [pa, pc] : part) a += pa, c += pc;
  return a + c;
}

}  // namespace al
