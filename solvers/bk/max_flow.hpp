// Minimum s-t cut on a CSR graph with terminal arcs, via Boost.Graph's
// boykov_kolmogorov_max_flow (BSL-1.0). Shared by the bk, cp and exact solvers.
//
// Cut cost of a partition (S = source side, T = sink side):
//   sum_{v in T} source_cap[v] + sum_{v in S} sink_cap[v]
//   + sum_{edges u->v with u in S, v in T} cap(u->v)
// i.e. source_cap[v] is what v pays for ending on the sink side, sink_cap[v] what it pays for the
// source side. Edges are given in the RefineProblem CSR layout (first_edge[V+1], adj_vertices[E],
// each undirected edge once); forward_cap[e] is the capacity of u->adj_vertices[e], reverse_cap[e]
// that of the opposite arc (empty reverse_cap = symmetric: reverse = forward).
// Capacities must be >= 0 (NaN is an error); +infinity is allowed (hard constraint) and replaced
// internally by a finite value larger than any finite cut.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace al {

struct MinCutResult {
  std::vector<std::uint8_t> source_side;  // V: 1 if v is on the source side of a minimum cut
  double cut_value = 0.0;                 // minimum cut (= max flow), constants included
  double build_seconds = 0.0;             // building the Boost network
  double flow_seconds = 0.0;              // boykov_kolmogorov_max_flow itself
};

// The returned source side is the set of nodes reachable from the source in the final residual
// graph (the smallest minimum-cut source set). Deterministic. Throws al::Error on bad sizes or
// negative/NaN capacities.
MinCutResult MinCutLabels(std::span<const double> source_cap, std::span<const double> sink_cap,
                          std::span<const std::int64_t> first_edge,
                          std::span<const std::int32_t> adj_vertices,
                          std::span<const double> forward_cap,
                          std::span<const double> reverse_cap = {});

}  // namespace al
