// Level-set partition of the two-label relaxed problem (CUT_PURSUIT.md §11), shared by the exact
// solver (to rounding: epsilon 1e-10) and cut pursuit's initialisation (a coarse epsilon).
//
// For D = 2 the problem is 1-D total variation with a separable convex loss:
//   min_p  Σ_v φ_v(p_v) + Σ_e ω_e |p_u − p_v|,   p ∈ [0, 1]^V,
//   φ_v(p) = w_v [ℓ_s(y_v0, p) + ℓ_s(y_v1, 1 − p)],  ω_e = omega_scale · w_e.
// The upper level sets of the optimum are nested minimum cuts, so a connected piece U known to lie
// in [lo, hi] is cut at a level t (its best constant given its boundary, or the interval's middle):
// the sink side lies in [t, hi], the source side in [lo, t]; each side's connected components are
// new pieces. A piece whose cut gains nothing is an optimal plateau (exact to rounding); a piece
// whose interval is narrower than epsilon is final at its best constant (an approximation of order
// epsilon). Pieces of one depth are independent (their neighbours outside lie entirely above or
// below), so each depth's pieces are cut in parallel; each piece's cut depends only on the piece,
// so the result does not depend on the number of threads.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "al/core/default_init_allocator.hpp"
#include "al/graph/loss.hpp"
#include "solvers/max_flow/max_flow.hpp"

namespace al::levelset {

// Both directions of every stored edge: the neighbours of v are nbr[first[v] .. first[v + 1]),
// reached through the stored edge edge[k] (in the order of the stored edges). Built with edge
// weights, an entry carries its edge's weight[k] instead of the edge id (edge stays empty): a
// caller that only needs the weight then reads it beside the neighbour, not at a random edge id.
struct SymmetricAdjacency {
  // The entries are sized, then every one written by the build's parallel fill: no serial zero
  // fill first (default_init_allocator.hpp; 96 MB at 3M: 0.024 s on one thread).
  template <class T>
  using Entries = std::vector<T, DefaultInitAllocator<T>>;
  std::vector<std::int64_t> first;
  Entries<std::int32_t> nbr;
  Entries<std::int64_t> edge;
  Entries<double> weight;
};
SymmetricAdjacency BuildSymmetricAdjacency(std::span<const std::int64_t> first_edge,
                                           std::span<const std::int32_t> adj_vertices,
                                           std::span<const double> edge_weights = {});

struct TwoLabelTv {
  std::span<const std::int64_t> first_edge;    // V + 1 (CSR, every undirected edge stored once)
  std::span<const std::int32_t> adj_vertices;  // E
  std::span<const double> edge_weights;        // E, finite, >= 0
  std::span<const double> y;                   // V x 2: (y_v0, y_v1), p is the coordinate 0
  std::span<const double> node_weights;        // V (empty = all 1)
  double omega_scale = 2.0;                    // m_0 + m_1 (2 for the unit metric)
  Loss loss{0.1, 2};
  const SymmetricAdjacency* adjacency = nullptr;  // the caller's, if it has one (else built here)

  std::int32_t num_nodes() const { return static_cast<std::int32_t>(first_edge.size()) - 1; }
};

struct Options {
  double epsilon = 1e-10;  // a piece whose interval is at most this wide is final
  bool bisection = false;  // pivot at the interval's middle (the spec's reference) instead of
                           // the piece's best constant
  int num_threads = 1;     // never changes the result
  MaxFlow::Algorithm max_flow = MaxFlow::Algorithm::kHybrid;
};

struct Partition {
  std::vector<std::int32_t> piece;     // per node; pieces numbered by their smallest node (§12)
  std::vector<double> value;           // per piece: its p
  std::vector<double> lo, hi;          // per piece: the interval known to hold its nodes' optima
  std::vector<std::uint8_t> plateau;   // per piece: 1 = proven optimal plateau (cut gained nothing)
  std::int64_t max_flows = 0;
  int max_depth = 0;
};

// Optional reusable max-flow networks, one per thread (nullptr or too few: made locally).
Partition SolveLevelSets(const TwoLabelTv& problem, const Options& options,
                         std::vector<MaxFlow>* networks = nullptr);

}  // namespace al::levelset
