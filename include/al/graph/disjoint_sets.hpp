// Disjoint sets over 0..n−1 (union–find with path halving). A union makes the smaller index the
// root, so every set's root is its smallest member whatever the order of the unions: results
// built on roots do not depend on edge order.
#pragma once
#include <algorithm>
#include <atomic>
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

// The same sets built by many threads at once: unions and finds may run concurrently (links and
// path halving by compare-and-swap). A parent is never above its child's index, so links cannot
// form a cycle and every root is still its set's smallest member: Find after the unions gives
// exactly DisjointSets' roots, whatever the threads' interleaving.
class ConcurrentDisjointSets {
 public:
  explicit ConcurrentDisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::int32_t Find(std::int32_t x) {
    for (;;) {
      std::int32_t p = Parent(x);
      if (p == x) return x;
      const std::int32_t g = Parent(p);
      if (g != p) Ref(x).compare_exchange_weak(p, g, std::memory_order_relaxed);
      x = g;
    }
  }
  void Unite(std::int32_t a, std::int32_t b) {
    for (;;) {
      a = Find(a), b = Find(b);
      if (a == b) return;
      if (a < b) std::swap(a, b);
      std::int32_t expected = a;  // a still a root: it goes under the smaller root b
      if (Ref(a).compare_exchange_strong(expected, b, std::memory_order_relaxed)) return;
    }
  }

 private:
  std::atomic_ref<std::int32_t> Ref(std::int32_t x) { return std::atomic_ref<std::int32_t>(parent_[std::size_t(x)]); }
  std::int32_t Parent(std::int32_t x) { return Ref(x).load(std::memory_order_relaxed); }
  std::vector<std::int32_t> parent_;
};

}  // namespace al
