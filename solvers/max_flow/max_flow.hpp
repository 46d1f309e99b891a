// The project's one max-flow / minimum s-t cut module, shared by the bk, cp and exact solvers.
//
// MaxFlow::Solve() runs two phases on one residual network (CSR arcs built once per Solve(); all
// buffers kept between Reset() calls, so the many small cuts of cut pursuit and of the exact level-set
// solver allocate nothing in steady state; deterministic: no randomness, fixed visiting orders):
//  1. pseudoflow (pseudoflow.cpp): Hochbaum's highest-label pseudoflow algorithm (Operations
//     Research 56(4), 2008), written for this project from the paper. It moves the bulk of the flow
//     by merging trees of excess into trees of deficit, which is what the balanced, long-range cuts
//     of cut pursuit need (docs/solvers.md "Max-flow": 1.7-14x faster than BK alone there);
//  2. Boykov-Kolmogorov augmenting paths with search-tree reuse (Boykov & Kolmogorov, PAMI 2004;
//     max_flow.cpp), started from whatever phase 1 left. Any pseudoflow is a valid start once node
//     excesses are read as terminal residuals, so the result is exact whatever phase 1 did; after a
//     complete phase 1 this pass finds no augmenting path and only grows the final search trees.
// The default, Algorithm::kHybrid, first runs BK alone with a work budget of two sweeps over the
// network: cuts where most excess is stranded or paths are short end there (BK is at its best on
// them); the others continue with phase 1 from BK's flow, then phase 2. kPseudoflowThenBk and
// kBoykovKolmogorov (the behaviour before pseudoflow was added) are kept for tests and benchmarks.
// The GPL codes of Kolmogorov / pcp and the academic-licence HPF code are not used.
//
// Cut cost of a partition (S = source side, T = sink side):
//   sum_{v in T} source_cap[v] + sum_{v in S} sink_cap[v]
//   + sum_{edges u->v with u in S, v in T} cap(u->v)
// i.e. source_cap[v] is what v pays for ending on the sink side, sink_cap[v] what it pays for the
// source side. The returned source side is the set of nodes reachable from the source in the final
// residual graph (the smallest minimum-cut source set), whichever algorithm ran.
//
// MinCutLabels: the same cut on the RefineProblem CSR layout with input validation and +infinity
// capacities (hard constraints). MinCutLabelsBoost: identical contract computed with Boost.Graph's
// boykov_kolmogorov_max_flow (BSL-1.0); kept only as an independent cross-check in tests and as the
// baseline of bench/bk_bench.cpp (docs/solvers.md has the measured reason for not using it).
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "al/core/huge_page_allocator.hpp"

namespace al {

class MaxFlow {
 public:
  enum class Algorithm {
    kHybrid,            // default: BK while it stays cheap, else phase 1, then BK (see Solve())
    kPseudoflowThenBk,  // phase 1 + 2 above
    kBoykovKolmogorov,  // phase 2 only (the algorithm before pseudoflow was added)
  };
  // Option names "hybrid", "pseudoflow", "bk" (solver JSON options "max_flow"); nullopt if unknown.
  static const char* AlgorithmName(Algorithm algorithm);
  // Every algorithm with its option name (the "max_flow" key of cp and exact), default first.
  static std::vector<std::pair<std::string, Algorithm>> AlgorithmNames();
  // Work counters of the last Solve() (diagnostics; never influence the result).
  struct Stats {
    std::int64_t augmentations = 0;        // BK augmenting paths
    std::int64_t mergers = 0;              // pseudoflow: trees of excess hung below another tree
    std::int64_t relabels = 0;             // pseudoflow: node label increments
    std::int64_t gap_lifts = 0;            // pseudoflow: trees found unable to reach a deficit
    bool budget_exhausted = false;         // pseudoflow stopped by its safety valve (BK finished)
  };

  // huge_pages = false: the large buffers are not advised onto transparent huge pages. For a network
  // built and solved once (MinCutLabels: the bk solver's one cut per round). With the kernel's THP
  // defrag "madvise", an advised first touch may wait for memory compaction: on this project's
  // shared VMs the bk cut of the 3M scene (8M arcs) then took 0.45-0.54 s to build instead of
  // 0.15-0.19 s (3 runs each). Cut pursuit's networks (level-set start, splits) go without the
  // advice too (cut_pursuit.cpp: its first cuts fill them at once); exact keeps it.
  explicit MaxFlow(bool huge_pages = true);

  void set_algorithm(Algorithm algorithm) { algorithm_ = algorithm; }
  // Starts a new network of num_nodes nodes without terminal capacities or edges.
  void Reset(std::int32_t num_nodes);
  // Optional, after Reset(): room for this many edges, so that AddEdge does not regrow the edge
  // buffers (each regrowth touches fresh memory, which costs more than the copy on this project's
  // VMs). Never changes a result.
  void Reserve(std::int64_t num_edges);
  // Adds terminal capacities (both >= 0, finite): source_cap is paid when v ends on the sink side,
  // sink_cap when it ends on the source side. May be called several times per node.
  void AddTerminal(std::int32_t v, double source_cap, double sink_cap);
  // Signed unary: a > 0 is a source arc of capacity a, a < 0 a sink arc of capacity -a.
  void AddUnary(std::int32_t v, double a) { a > 0.0 ? AddTerminal(v, a, 0.0) : AddTerminal(v, 0.0, -a); }
  // Edge with capacity cap_uv from u to v and cap_vu from v to u (finite, >= 0; u != v).
  void AddEdge(std::int32_t u, std::int32_t v, double cap_uv, double cap_vu);
  // All edges at once in the RefineProblem CSR layout, instead of AddEdge: node u's edges are
  // [first_edge[u], first_edge[u + 1]), adj[e] the other end (!= u); the arc u -> adj[e] has
  // capacity forward[e], the opposite arc reverse[e] (empty reverse: = forward; finite, >= 0).
  // The arcs are laid out straight from the spans: no edge list is staged and nodes keep the
  // caller's numbering (no breadth-first renumbering), so one large cut first touches less than
  // half the memory and makes two passes over the edges instead of five (the bk solver's single
  // cut of 685k nodes and 4.0M edges spent more time there than in the flow). The spans must stay
  // valid until Solve() returns. A network takes its edges from AddEdge or from SetEdges, not both;
  // Reset() forgets them.
  void SetEdges(std::span<const std::int64_t> first_edge, std::span<const std::int32_t> adj,
                std::span<const double> forward, std::span<const double> reverse = {});
  // Computes a maximum flow; returns the cost of the returned minimum cut (terminal constants
  // included), summed in a fixed order from the capacities as given.
  double Solve();
  // After Solve(): true if v is on the source side of the minimum cut.
  bool SourceSide(std::int32_t v) const {
    const Node& x = nodes_[perm_[v]];
    return x.parent != kFree && !x.sink;
  }
  std::int32_t num_nodes() const { return n_; }
  std::int64_t num_augmentations() const { return stats_.augmentations; }
  const Stats& stats() const { return stats_; }

 private:
  static constexpr std::int32_t kFree = -1, kTerminal = -2, kOrphan = -3;
  static constexpr std::int32_t kNotQueued = -1, kQueueEnd = -2;

  // Everything the search touches per node / per arc sits in one 32- / 16-byte record, so a visit
  // costs one cache line instead of one per array (the networks of a 100k-node split do not fit in
  // L2).
  struct Node {
    double tr;           // terminal residual: > 0 to the source, < 0 to the sink
    std::int32_t first;  // first arc (CSR; the sentinel node n holds the end)
    std::int32_t parent; // arc to the parent in its tree, or kFree / kTerminal / kOrphan
    std::int32_t ts;     // timestamp of dist
    std::int32_t dist;   // distance-to-terminal estimate
    std::int32_t next;   // active FIFO link (kNotQueued / kQueueEnd)
    std::int32_t sink;   // 1 if the node belongs to the sink tree
  };
  struct Arc {
    std::int32_t head;    // node the arc points to
    std::int32_t sister;  // the opposite arc
    double rcap;          // residual capacity
  };

  // Per-node state of the pseudoflow phase: the tree the node belongs to (children in a doubly
  // linked sibling list, so a split is O(1)), its label, and the scan positions of the search.
  struct TreeNode {
    std::int32_t label;
    std::int32_t parent;        // -1 for a root (only roots carry excess)
    std::int32_t parent_arc;    // arc node -> parent
    std::int32_t first_child, next_sibling, prev_sibling;
    std::int32_t next_scan;     // next child to visit in the depth-first search
    std::int32_t next_arc;      // first arc not yet known to be useless at the current label
    std::int32_t bucket_next;   // FIFO link among the strong roots of one label
  };

  void Build();
  void BuildFromCsr();
  int CsrBuildParts() const;
  void BuildFromCsrParallel(int parts);
  double CutValue() const;
  void GreedyPreflow();
  bool BoykovKolmogorov(std::int64_t max_work);
  void ResetTrees();
  std::int32_t GrowFrom(std::int32_t i);
  void Pseudoflow();
  void TreeLink(std::int32_t child, std::int32_t parent, std::int32_t arc);
  void TreeUnlink(std::int32_t child);
  void BucketAdd(std::int32_t root);
  std::int32_t BucketPop(std::int32_t label);
  std::int32_t HighestStrongRoot();
  void SetLabels(std::int32_t root, std::int32_t only_label, std::int32_t to);
  void ProcessRoot(std::int32_t root);
  std::int32_t FindMerger(std::int32_t v, std::int32_t label);
  void RelabelIfDone(std::int32_t v, std::int32_t label);
  void MergeAndPush(std::int32_t strong_node, std::int32_t arc, std::int32_t root);
  void Activate(std::int32_t v);
  std::int32_t NextActive();
  void MakeOrphan(std::int32_t v);
  void Augment(std::int32_t middle_arc);
  void Adopt();
  void ProcessOrphan(std::int32_t v);

  Algorithm algorithm_ = Algorithm::kHybrid;
  std::int32_t n_ = 0;
  double constant_ = 0.0;  // common part of the terminal capacities: paid by every cut
  Stats stats_;
  std::int64_t work_ = 0;  // BK arc and tree-path visits: its running cost, for the hybrid's budget
  // Large per-cut buffers: huge pages make their first touch cheap (huge_page_allocator.hpp).
  template <class T>
  using Buffer = std::vector<T, HugePageAllocator<T>>;
  // Input in the caller's numbering (until Build()), from AddEdge or SetEdges.
  struct CsrEdges {
    std::span<const std::int64_t> first;
    std::span<const std::int32_t> adj;
    std::span<const double> forward, reverse;
  };
  std::optional<CsrEdges> csr_;
  Buffer<double> user_tr_;
  Buffer<std::int32_t> eu_, ev_;
  Buffer<double> ecap_uv_, ecap_vu_;
  // Internal numbering: breadth-first order over the edges (perm_[user id] = internal id), so that
  // nodes adjacent in the graph are mostly adjacent in memory whatever the caller's numbering.
  Buffer<std::int32_t> perm_, order_, ufirst_, uadj_, uslot_;
  Buffer<Node> nodes_;  // n + 1 (sentinel)
  Buffer<Arc> arcs_;
  std::int32_t queue_first_ = kQueueEnd, queue_last_ = kQueueEnd;
  std::vector<std::int32_t> orphans_;
  std::size_t orphan_head_ = 0;
  std::int32_t time_ = 0;
  // Pseudoflow phase.
  Buffer<TreeNode> tree_;
  Buffer<std::int32_t> bucket_first_, bucket_last_, label_count_;
  std::vector<std::int32_t> stack_;
  std::int32_t highest_ = 0;
};

struct MinCutResult {
  std::vector<std::uint8_t> source_side;  // V: 1 if v is on the source side of a minimum cut
  double cut_value = 0.0;                 // minimum cut (= max flow), constants included
  double build_seconds = 0.0;             // building the network
  double flow_seconds = 0.0;              // the max-flow itself
};

// Edges are given in the RefineProblem CSR layout (first_edge[V+1], adj_vertices[E], each undirected
// edge once); forward_cap[e] is the capacity of u->adj_vertices[e], reverse_cap[e] that of the
// opposite arc (empty reverse_cap = symmetric: reverse = forward). Capacities must be >= 0 (NaN is an
// error); +infinity is allowed (hard constraint) and replaced internally by a finite value larger than
// any finite cut. Deterministic. Throws al::Error on bad sizes, bad adjacency or negative/NaN
// capacities.
MinCutResult MinCutLabels(std::span<const double> source_cap, std::span<const double> sink_cap,
                          std::span<const std::int64_t> first_edge,
                          std::span<const std::int32_t> adj_vertices,
                          std::span<const double> forward_cap,
                          std::span<const double> reverse_cap = {});

// Same contract, computed with Boost.Graph's boykov_kolmogorov_max_flow (reference / baseline).
MinCutResult MinCutLabelsBoost(std::span<const double> source_cap, std::span<const double> sink_cap,
                               std::span<const std::int64_t> first_edge,
                               std::span<const std::int32_t> adj_vertices,
                               std::span<const double> forward_cap,
                               std::span<const double> reverse_cap = {});

}  // namespace al
