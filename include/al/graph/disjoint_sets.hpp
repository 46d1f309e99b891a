// Disjoint sets over 0..n−1 (union–find with path halving). A union makes the smaller index the
// root, so every set's root is its smallest member whatever the order of the unions: results
// built on roots do not depend on edge order.
#pragma once
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace al {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::int32_t Find(std::int32_t x) {
    while (parent_[std::size_t(x)] != x) x = parent_[std::size_t(x)] = parent_[std::size_t(parent_[std::size_t(x)])];
    return x;
  }
  void Unite(std::int32_t a, std::int32_t b) {
    a = Find(a), b = Find(b);
    if (a != b) parent_[std::size_t(std::max(a, b))] = std::min(a, b);
  }

 private:
  std::vector<std::int32_t> parent_;
};

}  // namespace al
