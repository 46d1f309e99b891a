// MinCutLabels (validation, +infinity -> a finite "big" capacity, then al::MaxFlow) and the Boost
// reference MinCutLabelsBoost. The Boost network is built once, directly in CSR form (no per-edge
// map lookups): each undirected edge becomes two arcs that are each other's reverse (both carrying
// capacity); each node keeps at most one terminal arc: the common part of its two terminal
// capacities is a constant of the cut and is folded into cut_value.
#include "solvers/max_flow/max_flow.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/property_map/property_map.hpp>

#include "al/core/error.hpp"
#include "al/core/timer.hpp"

namespace al {
namespace {

using Graph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property,
                                                 boost::no_property, boost::no_property,
                                                 std::uint32_t, std::uint32_t>;
using EdgeDesc = boost::graph_traits<Graph>::edge_descriptor;

void CheckCap(double c, const char* what) {
  if (std::isnan(c) || c < 0.0)
    throw Error(std::string("MinCutLabels: ") + what + " capacity is negative or NaN",
                ExitCode::kInternal);
}

// Checks sizes, adjacency and capacities; returns the finite stand-in for +infinity.
double CheckedBigCapacity(std::span<const double> source_cap, std::span<const double> sink_cap,
                          std::span<const std::int64_t> first_edge,
                          std::span<const std::int32_t> adj_vertices,
                          std::span<const double> forward_cap, std::span<const double> reverse_cap) {
  const std::size_t V = source_cap.size();
  const std::size_t E = adj_vertices.size();
  if (sink_cap.size() != V || first_edge.size() != V + 1 || forward_cap.size() != E ||
      (!reverse_cap.empty() && reverse_cap.size() != E) || first_edge[0] != 0 ||
      static_cast<std::size_t>(first_edge[V]) != E)
    throw Error("MinCutLabels: inconsistent array sizes", ExitCode::kInternal);
  if (V + 2 > std::numeric_limits<std::uint32_t>::max() / 2 ||
      2 * E + 2 * V > std::numeric_limits<std::int32_t>::max())
    throw Error("MinCutLabels: graph too large", ExitCode::kInternal);
  for (std::size_t u = 0; u < V; ++u) {
    if (first_edge[u + 1] < first_edge[u])
      throw Error("MinCutLabels: first_edge is not monotone", ExitCode::kInternal);
    for (std::int64_t e = first_edge[u]; e < first_edge[u + 1]; ++e) {
      const std::int32_t v = adj_vertices[e];
      if (v < 0 || static_cast<std::size_t>(v) >= V || static_cast<std::size_t>(v) == u)
        throw Error("MinCutLabels: bad adjacency", ExitCode::kInternal);
    }
  }
  // Infinite capacities become one value larger than any finite cut.
  double finite_sum = 0.0;
  auto scan = [&](std::span<const double> caps, const char* what) {
    for (double c : caps) {
      CheckCap(c, what);
      if (!std::isinf(c)) finite_sum += c;
    }
  };
  scan(source_cap, "source");
  scan(sink_cap, "sink");
  scan(forward_cap, "edge");
  scan(reverse_cap, "edge");
  return 2.0 * finite_sum + 1.0;
}

}  // namespace

MinCutResult MinCutLabels(std::span<const double> source_cap, std::span<const double> sink_cap,
                          std::span<const std::int64_t> first_edge,
                          std::span<const std::int32_t> adj_vertices,
                          std::span<const double> forward_cap,
                          std::span<const double> reverse_cap) {
  Timer timer;
  const double big =
      CheckedBigCapacity(source_cap, sink_cap, first_edge, adj_vertices, forward_cap, reverse_cap);
  auto fin = [&](double c) { return std::isinf(c) ? big : c; };
  const std::size_t V = source_cap.size();
  MinCutResult result;
  result.source_side.assign(V, 0);
  if (V == 0) return result;
  MaxFlow mf(/*huge_pages=*/false);  // one network, one cut (MaxFlow's constructor says why)
  mf.Reset(static_cast<std::int32_t>(V));
  for (std::size_t v = 0; v < V; ++v)
    mf.AddTerminal(static_cast<std::int32_t>(v), fin(source_cap[v]), fin(sink_cap[v]));
  // The edges go to the network as they are; only a capacity of +infinity needs a finite copy.
  auto has_infinity = [](std::span<const double> c) { return std::any_of(c.begin(), c.end(), [](double x) { return std::isinf(x); }); };
  std::vector<double> finite_forward, finite_reverse;
  if (has_infinity(forward_cap) || has_infinity(reverse_cap)) {
    const std::span<const double> rev = reverse_cap.empty() ? forward_cap : reverse_cap;
    for (std::size_t e = 0; e < forward_cap.size(); ++e) {
      finite_forward.push_back(fin(forward_cap[e]));
      finite_reverse.push_back(fin(rev[e]));
    }
    forward_cap = finite_forward;
    reverse_cap = finite_reverse;
  }
  mf.SetEdges(first_edge, adj_vertices, forward_cap, reverse_cap);
  result.build_seconds = timer.Seconds();  // Solve() also lays out the CSR arcs (counted as flow)
  Timer flow_timer;
  result.cut_value = mf.Solve();
  result.flow_seconds = flow_timer.Seconds();
  for (std::size_t v = 0; v < V; ++v)
    result.source_side[v] = mf.SourceSide(static_cast<std::int32_t>(v)) ? 1 : 0;
  return result;
}

namespace {

// The s-t network in Boost's CSR layout: arcs sorted by tail, each with its reverse's index.
struct BoostNetwork {
  std::uint32_t s = 0, t = 0;
  std::size_t N = 0;
  double constant = 0.0;  // the common part of each node's two terminal capacities
  std::vector<std::pair<std::uint32_t, std::uint32_t>> arcs;
  std::vector<double> cap;
  std::vector<std::uint32_t> rev;
};

BoostNetwork BuildBoostNetwork(std::span<const double> source_cap, std::span<const double> sink_cap,
                               std::span<const std::int64_t> first_edge, std::span<const std::int32_t> adj_vertices,
                               std::span<const double> forward_cap, std::span<const double> reverse_cap, double big) {
  auto fin = [&](double c) { return std::isinf(c) ? big : c; };
  const std::size_t V = source_cap.size();
  BoostNetwork net;
  // Net terminal capacity per node: > 0 source arc, < 0 sink arc.
  std::vector<double> terminal(V);
  for (std::size_t v = 0; v < V; ++v) {
    const double a = fin(source_cap[v]), b = fin(sink_cap[v]);
    net.constant += std::min(a, b);
    terminal[v] = a - b;
  }
  net.s = static_cast<std::uint32_t>(V);
  net.t = net.s + 1;
  net.N = V + 2;
  // Out-degrees, then prefix offsets (arcs sorted by source, so arc index = position).
  std::vector<std::uint32_t> offset(net.N + 1, 0);
  for (std::size_t u = 0; u < V; ++u) {
    for (std::int64_t e = first_edge[u]; e < first_edge[u + 1]; ++e) {
      ++offset[u + 1];
      ++offset[adj_vertices[e] + 1];
    }
    if (terminal[u] != 0.0) {
      ++offset[u + 1];
      ++offset[(terminal[u] > 0 ? net.s : net.t) + 1];
    }
  }
  for (std::size_t i = 0; i < net.N; ++i) offset[i + 1] += offset[i];
  const std::size_t A = offset[net.N];
  std::vector<std::uint32_t> cursor(offset.begin(), offset.end() - 1);
  net.arcs.resize(A);
  net.cap.assign(A, 0.0);
  net.rev.resize(A);
  auto add_pair = [&](std::uint32_t a, std::uint32_t b, double cab, double cba) {
    const std::uint32_t i = cursor[a]++, j = cursor[b]++;
    net.arcs[i] = {a, b};
    net.arcs[j] = {b, a};
    net.cap[i] = cab;
    net.cap[j] = cba;
    net.rev[i] = j;
    net.rev[j] = i;
  };
  for (std::size_t u = 0; u < V; ++u) {
    const auto uu = static_cast<std::uint32_t>(u);
    if (terminal[u] > 0) add_pair(net.s, uu, terminal[u], 0.0);
    else if (terminal[u] < 0) add_pair(uu, net.t, -terminal[u], 0.0);
    for (std::int64_t e = first_edge[u]; e < first_edge[u + 1]; ++e) {
      const double f = fin(forward_cap[e]);
      add_pair(uu, static_cast<std::uint32_t>(adj_vertices[e]), f, reverse_cap.empty() ? f : fin(reverse_cap[e]));
    }
  }
  return net;
}

}  // namespace

MinCutResult MinCutLabelsBoost(std::span<const double> source_cap, std::span<const double> sink_cap,
                               std::span<const std::int64_t> first_edge,
                               std::span<const std::int32_t> adj_vertices,
                               std::span<const double> forward_cap,
                               std::span<const double> reverse_cap) {
  Timer timer;
  const double big =
      CheckedBigCapacity(source_cap, sink_cap, first_edge, adj_vertices, forward_cap, reverse_cap);
  const std::size_t V = source_cap.size();
  MinCutResult result;
  result.source_side.assign(V, 0);
  if (V == 0) return result;
  BoostNetwork net = BuildBoostNetwork(source_cap, sink_cap, first_edge, adj_vertices, forward_cap, reverse_cap, big);
  const std::size_t A = net.arcs.size();
  Graph g(boost::edges_are_sorted, net.arcs.begin(), net.arcs.end(), net.N);
  auto eidx = get(boost::edge_index, g);
  std::vector<EdgeDesc> rev_desc(A);
  for (std::size_t i = 0; i < A; ++i) rev_desc[i] = EdgeDesc(net.arcs[net.rev[i]].first, net.rev[i]);
  std::vector<double> residual(A, 0.0);
  std::vector<EdgeDesc> pred(net.N);
  std::vector<boost::default_color_type> color(net.N);
  std::vector<long> dist(net.N, 0);
  auto vidx = get(boost::vertex_index, g);
  result.build_seconds = timer.Seconds();

  Timer flow_timer;
  const double flow = boost::boykov_kolmogorov_max_flow(
      g, boost::make_iterator_property_map(net.cap.begin(), eidx),
      boost::make_iterator_property_map(residual.begin(), eidx),
      boost::make_iterator_property_map(rev_desc.begin(), eidx),
      boost::make_iterator_property_map(pred.begin(), vidx),
      boost::make_iterator_property_map(color.begin(), vidx),
      boost::make_iterator_property_map(dist.begin(), vidx), vidx, net.s, net.t);
  result.flow_seconds = flow_timer.Seconds();
  result.cut_value = flow + net.constant;
  // Black = source tree = reachable from s in the residual graph.
  for (std::size_t v = 0; v < V; ++v)
    result.source_side[v] = color[v] == boost::black_color ? 1 : 0;
  return result;
}

}  // namespace al
