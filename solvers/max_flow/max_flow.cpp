// Boykov-Kolmogorov max-flow (phase 2 of MaxFlow::Solve, see max_flow.hpp). Two search trees grow
// from the terminals over non-saturated arcs; when they touch, the path is augmented, saturated tree
// arcs turn their child into an orphan, and orphans try to re-attach to a node of their own tree whose
// root path is still valid ("adoption", with timestamps/distances so validity checks stop early and
// prefer short paths). Unlike Dinic, the trees survive augmentations, which is why this is much
// faster on the kNN graphs of al-refine (few long augmenting paths, many short ones).
//
// Conventions: node.parent is the arc v -> parent. In the source tree flow runs parent -> v, so the
// arc that must stay non-saturated is the parent arc's sister; in the sink tree the parent arc itself.
// Node terminal residuals (tr) may already hold a pseudoflow's excesses when this phase starts.
#include "solvers/max_flow/max_flow.hpp"

#include "al/core/block_sum.hpp"
#include "al/core/range_scatter.hpp"

#include <omp.h>

#include <algorithm>
#include <limits>

namespace al {

MaxFlow::MaxFlow(bool huge_pages)
    : user_tr_(HugePageAllocator<double>(huge_pages)),
      eu_(HugePageAllocator<std::int32_t>(huge_pages)),
      ev_(HugePageAllocator<std::int32_t>(huge_pages)),
      ecap_uv_(HugePageAllocator<double>(huge_pages)),
      ecap_vu_(HugePageAllocator<double>(huge_pages)),
      perm_(HugePageAllocator<std::int32_t>(huge_pages)),
      order_(HugePageAllocator<std::int32_t>(huge_pages)),
      ufirst_(HugePageAllocator<std::int32_t>(huge_pages)),
      uadj_(HugePageAllocator<std::int32_t>(huge_pages)),
      uslot_(HugePageAllocator<std::int32_t>(huge_pages)),
      nodes_(HugePageAllocator<Node>(huge_pages)),
      arcs_(HugePageAllocator<Arc>(huge_pages)),
      tree_(HugePageAllocator<TreeNode>(huge_pages)),
      bucket_first_(HugePageAllocator<std::int32_t>(huge_pages)),
      bucket_last_(HugePageAllocator<std::int32_t>(huge_pages)),
      label_count_(HugePageAllocator<std::int32_t>(huge_pages)) {}

void MaxFlow::Reset(std::int32_t num_nodes) {
  n_ = num_nodes;
  constant_ = 0.0;
  stats_ = Stats{};
  work_ = 0;
  eu_.clear();
  ev_.clear();
  ecap_uv_.clear();
  ecap_vu_.clear();
  csr_.reset();
  user_tr_.assign(num_nodes, 0.0);
}

void MaxFlow::SetEdges(std::span<const std::int64_t> first_edge, std::span<const std::int32_t> adj,
                       std::span<const double> forward, std::span<const double> reverse) {
  eu_.clear();
  ev_.clear();
  ecap_uv_.clear();
  ecap_vu_.clear();
  csr_ = CsrEdges{first_edge, adj, forward, reverse.empty() ? forward : reverse};
}

void MaxFlow::AddTerminal(std::int32_t v, double source_cap, double sink_cap) {
  // Only the difference needs an arc; the common part is paid by every cut.
  const double delta = user_tr_[v];
  if (delta > 0.0) source_cap += delta;
  else sink_cap -= delta;
  constant_ += std::min(source_cap, sink_cap);
  user_tr_[v] = source_cap - sink_cap;
}

void MaxFlow::Reserve(std::int64_t num_edges) {
  const auto m = static_cast<std::size_t>(num_edges);
  eu_.reserve(m);
  ev_.reserve(m);
  ecap_uv_.reserve(m);
  ecap_vu_.reserve(m);
}

void MaxFlow::AddEdge(std::int32_t u, std::int32_t v, double cap_uv, double cap_vu) {
  if (!(cap_uv > 0.0) && !(cap_vu > 0.0)) return;
  eu_.push_back(u);
  ev_.push_back(v);
  ecap_uv_.push_back(cap_uv);
  ecap_vu_.push_back(cap_vu);
}

void MaxFlow::Build() {
  const std::int32_t n = n_;
  const std::size_t m = eu_.size();
  // Adjacency in the caller's numbering; uslot_ records each edge end's slot.
  ufirst_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (std::size_t e = 0; e < m; ++e) {
    ++ufirst_[eu_[e] + 1];
    ++ufirst_[ev_[e] + 1];
  }
  for (std::int32_t v = 0; v < n; ++v) ufirst_[v + 1] += ufirst_[v];
  uadj_.resize(2 * m);
  uslot_.resize(2 * m);
  perm_.assign(ufirst_.begin(), ufirst_.end() - 1);  // borrowed as fill cursor
  for (std::size_t e = 0; e < m; ++e) {
    const std::int32_t i = perm_[eu_[e]]++, j = perm_[ev_[e]]++;
    uadj_[i] = ev_[e];
    uadj_[j] = eu_[e];
    uslot_[2 * e] = i;
    uslot_[2 * e + 1] = j;
  }
  // Breadth-first renumbering, roots in increasing caller index (deterministic).
  perm_.assign(n, -1);
  order_.resize(n);
  std::int32_t count = 0;
  for (std::int32_t r = 0; r < n; ++r) {
    if (perm_[r] >= 0) continue;
    std::int32_t head = count;
    perm_[r] = count;
    order_[count++] = r;
    while (head < count) {
      const std::int32_t u = order_[head++];
      for (std::int32_t k = ufirst_[u]; k < ufirst_[u + 1]; ++k) {
        const std::int32_t v = uadj_[k];
        if (perm_[v] >= 0) continue;
        perm_[v] = count;
        order_[count++] = v;
      }
    }
  }
  nodes_.resize(static_cast<std::size_t>(n) + 1);
  std::int32_t pos = 0;
  for (std::int32_t i = 0; i < n; ++i) {
    const std::int32_t u = order_[i];
    nodes_[i].tr = user_tr_[u];
    nodes_[i].first = pos;
    pos += ufirst_[u + 1] - ufirst_[u];
  }
  nodes_[n].first = pos;
  arcs_.resize(2 * m);
  // A caller slot k of node u keeps its rank among u's arcs (insertion order).
  auto slot = [&](std::int32_t k, std::int32_t u) { return nodes_[perm_[u]].first + (k - ufirst_[u]); };
  for (std::size_t e = 0; e < m; ++e) {
    const std::int32_t u = eu_[e], v = ev_[e];
    const std::int32_t i = slot(uslot_[2 * e], u), j = slot(uslot_[2 * e + 1], v);
    arcs_[i] = {perm_[v], j, ecap_uv_[e]};
    arcs_[j] = {perm_[u], i, ecap_vu_[e]};
  }
}

// The parallel layout applies to edges stored at their smaller end (every refine problem's and
// level-set piece's): node w's arcs are then the reverse arcs of the edges ending at w, sources
// ascending (RangeScatter), followed by w's own edges: the serial fill's order, so the same
// network. Inside a parallel region (the level-set workers) it stays serial.
int MaxFlow::CsrBuildParts() const {
  const CsrEdges& g = *csr_;
  if (omp_in_parallel() || g.adj.size() < (std::size_t{1} << 16) || !StoredAtSmallerEnd(g.first, g.adj)) return 1;
  return RangeScatter::DefaultParts();
}

void MaxFlow::BuildFromCsrParallel(int parts) {
  const std::int32_t n = n_;
  const CsrEdges& g = *csr_;
  RangeScatter scatter(n, std::size_t(n), parts);
#pragma omp parallel for schedule(static, 1) num_threads(parts)
  for (int t = 0; t < parts; ++t)
    for (std::int64_t e = g.first[scatter.Range(t).first]; e < g.first[scatter.Range(t).second]; ++e)
      scatter.Count(t, std::size_t(g.adj[e]));
  nodes_.resize(static_cast<std::size_t>(n) + 1);
  perm_.resize(n);
  std::int32_t pos = 0;
  for (std::int32_t w = 0; w < n; ++w) {
    perm_[w] = w;
    nodes_[w].tr = user_tr_[w];
    nodes_[w].first = pos;
    pos += static_cast<std::int32_t>(scatter.Total(std::size_t(w)) + (g.first[w + 1] - g.first[w]));
  }
  nodes_[n].first = pos;
  arcs_.resize(static_cast<std::size_t>(pos));
#pragma omp parallel for schedule(static, 1) num_threads(parts)
  for (int t = 0; t < parts; ++t)
    for (auto u = static_cast<std::int32_t>(scatter.Range(t).first); u < scatter.Range(t).second; ++u) {
      std::int32_t own = nodes_[u + 1].first - static_cast<std::int32_t>(g.first[u + 1] - g.first[u]);
      for (std::int64_t e = g.first[u]; e < g.first[u + 1]; ++e) {
        const std::int32_t v = g.adj[e];
        const std::int32_t i = own++, j = nodes_[v].first + scatter.Next(t, std::size_t(v));
        arcs_[i] = {v, j, g.forward[e]};
        arcs_[j] = {u, i, g.reverse[e]};
      }
    }
}

void MaxFlow::BuildFromCsr() {
  if (const int parts = CsrBuildParts(); parts > 1) return BuildFromCsrParallel(parts);
  const std::int32_t n = n_;
  const CsrEdges& g = *csr_;
  // Degrees, then each node's first arc; perm_ is the identity (SourceSide reads through it).
  nodes_.resize(static_cast<std::size_t>(n) + 1);
  perm_.resize(n);
  order_.resize(n);  // fill cursor
  for (std::int32_t u = 0; u < n; ++u) {
    perm_[u] = u;
    order_[u] = static_cast<std::int32_t>(g.first[u + 1] - g.first[u]);
  }
  for (std::size_t e = 0; e < g.adj.size(); ++e) ++order_[g.adj[e]];
  std::int32_t pos = 0;
  for (std::int32_t u = 0; u < n; ++u) {
    nodes_[u].tr = user_tr_[u];
    nodes_[u].first = pos;
    pos += order_[u];
    order_[u] = nodes_[u].first;
  }
  nodes_[n].first = pos;
  arcs_.resize(static_cast<std::size_t>(pos));
  for (std::int32_t u = 0; u < n; ++u)
    for (std::int64_t e = g.first[u]; e < g.first[u + 1]; ++e) {
      const std::int32_t v = g.adj[e];
      const std::int32_t i = order_[u]++, j = order_[v]++;
      arcs_[i] = {v, j, g.forward[e]};
      arcs_[j] = {u, i, g.reverse[e]};
    }
}

void MaxFlow::Activate(std::int32_t v) {
  if (nodes_[v].next != kNotQueued) return;
  nodes_[v].next = kQueueEnd;
  if (queue_last_ != kQueueEnd) nodes_[queue_last_].next = v;
  else queue_first_ = v;
  queue_last_ = v;
}

std::int32_t MaxFlow::NextActive() {
  while (queue_first_ != kQueueEnd) {
    const std::int32_t v = queue_first_;
    queue_first_ = nodes_[v].next;
    if (queue_first_ == kQueueEnd) queue_last_ = kQueueEnd;
    nodes_[v].next = kNotQueued;
    if (nodes_[v].parent != kFree) return v;  // freed nodes stay in the queue lazily
  }
  return kQueueEnd;
}

void MaxFlow::MakeOrphan(std::int32_t v) {
  nodes_[v].parent = kOrphan;
  orphans_.push_back(v);
}

void MaxFlow::Augment(std::int32_t middle) {
  // middle goes from the source tree (head of its sister) to the sink tree (its head).
  const std::int32_t s_end = arcs_[arcs_[middle].sister].head, t_end = arcs_[middle].head;
  double f = arcs_[middle].rcap;
  std::int32_t v = s_end;
  for (std::int32_t a; (a = nodes_[v].parent) != kTerminal; v = arcs_[a].head) {
    f = std::min(f, arcs_[arcs_[a].sister].rcap);
    ++work_;
  }
  f = std::min(f, nodes_[v].tr);
  v = t_end;
  for (std::int32_t a; (a = nodes_[v].parent) != kTerminal; v = arcs_[a].head) {
    f = std::min(f, arcs_[a].rcap);
    ++work_;
  }
  f = std::min(f, -nodes_[v].tr);

  arcs_[middle].rcap -= f;
  arcs_[arcs_[middle].sister].rcap += f;
  for (v = s_end;;) {
    const std::int32_t a = nodes_[v].parent;
    if (a == kTerminal) {
      nodes_[v].tr -= f;
      if (!(nodes_[v].tr > 0.0)) MakeOrphan(v);
      break;
    }
    const std::int32_t up = arcs_[a].head;
    arcs_[a].rcap += f;
    arcs_[arcs_[a].sister].rcap -= f;
    if (!(arcs_[arcs_[a].sister].rcap > 0.0)) MakeOrphan(v);
    v = up;
  }
  for (v = t_end;;) {
    const std::int32_t a = nodes_[v].parent;
    if (a == kTerminal) {
      nodes_[v].tr += f;
      if (!(nodes_[v].tr < 0.0)) MakeOrphan(v);
      break;
    }
    const std::int32_t up = arcs_[a].head;
    arcs_[arcs_[a].sister].rcap += f;
    arcs_[a].rcap -= f;
    if (!(arcs_[a].rcap > 0.0)) MakeOrphan(v);
    v = up;
  }
  ++stats_.augmentations;
}

void MaxFlow::ProcessOrphan(std::int32_t v) {
  const bool sink = nodes_[v].sink != 0;
  constexpr std::int32_t kInfDist = std::numeric_limits<std::int32_t>::max();
  std::int32_t best_arc = kFree, best_dist = kInfDist;
  for (std::int32_t a0 = nodes_[v].first; a0 < nodes_[v + 1].first; ++a0) {
    ++work_;
    // The arc that would carry flow between v and the candidate parent j must be non-saturated.
    if (!((sink ? arcs_[a0].rcap : arcs_[arcs_[a0].sister].rcap) > 0.0)) continue;
    const std::int32_t j = arcs_[a0].head;
    if ((nodes_[j].sink != 0) != sink || nodes_[j].parent == kFree) continue;
    // Is j's root path still valid (ends at the terminal without meeting an orphan)?
    std::int32_t d = 0, k = j;
    while (true) {
      ++work_;
      if (nodes_[k].ts == time_) { d += nodes_[k].dist; break; }
      const std::int32_t a = nodes_[k].parent;
      ++d;
      if (a == kTerminal) { nodes_[k].ts = time_; nodes_[k].dist = 1; break; }
      if (a == kOrphan) { d = kInfDist; break; }
      k = arcs_[a].head;
    }
    if (d == kInfDist) continue;
    if (d < best_dist) { best_arc = a0; best_dist = d; }
    for (k = j; nodes_[k].ts != time_; k = arcs_[nodes_[k].parent].head) {  // remember the path
      nodes_[k].ts = time_;
      nodes_[k].dist = d--;
    }
  }
  if (best_arc != kFree) {
    nodes_[v].parent = best_arc;
    nodes_[v].ts = time_;
    nodes_[v].dist = best_dist + 1;
    return;
  }
  // No valid parent: v becomes free; its children become orphans, neighbours that could reach it
  // again become active.
  nodes_[v].parent = kFree;
  for (std::int32_t a0 = nodes_[v].first; a0 < nodes_[v + 1].first; ++a0) {
    const std::int32_t j = arcs_[a0].head;
    const std::int32_t pj = nodes_[j].parent;
    if ((nodes_[j].sink != 0) != sink || pj == kFree) continue;
    if ((sink ? arcs_[a0].rcap : arcs_[arcs_[a0].sister].rcap) > 0.0) Activate(j);
    if (pj != kTerminal && pj != kOrphan && arcs_[pj].head == v) MakeOrphan(j);
  }
}

void MaxFlow::Adopt() {
  while (orphan_head_ < orphans_.size()) ProcessOrphan(orphans_[orphan_head_++]);
  orphans_.clear();
  orphan_head_ = 0;
}

const char* MaxFlow::AlgorithmName(Algorithm algorithm) {
  switch (algorithm) {
    case Algorithm::kHybrid: return "hybrid";
    case Algorithm::kPseudoflowThenBk: return "pseudoflow";
    case Algorithm::kBoykovKolmogorov: return "bk";
  }
  return "?";
}

std::vector<std::pair<std::string, MaxFlow::Algorithm>> MaxFlow::AlgorithmNames() {
  std::vector<std::pair<std::string, Algorithm>> names;
  for (Algorithm a : {Algorithm::kHybrid, Algorithm::kPseudoflowThenBk, Algorithm::kBoykovKolmogorov})
    names.emplace_back(AlgorithmName(a), a);
  return names;
}

double MaxFlow::Solve() {
  if (csr_) BuildFromCsr();
  else Build();
  GreedyPreflow();
  switch (algorithm_) {
    case Algorithm::kHybrid:
      // BK alone is best when it is done after about one sweep over the network (little flow, or
      // most excess stranded: 1.0-1.5 sweeps on every such cut measured); cuts that need long-range
      // transport take it 14-42 sweeps, and pseudoflow 1.7-14x less time (docs/solvers.md
      // "Max-flow").
      if (!BoykovKolmogorov(2 * (static_cast<std::int64_t>(n_) + static_cast<std::int64_t>(arcs_.size())))) {
        Pseudoflow();
        BoykovKolmogorov(-1);
      }
      break;
    case Algorithm::kPseudoflowThenBk:
      Pseudoflow();
      BoykovKolmogorov(-1);
      break;
    case Algorithm::kBoykovKolmogorov:
      BoykovKolmogorov(-1);
      break;
  }
  return CutValue();
}

void MaxFlow::GreedyPreflow() {
  const std::int32_t n = n_;
  // Greedy pre-flow over source-node -> sink-node arcs. When unaries dominate the edge capacities
  // (typical for cut pursuit splits and level cuts) most of the flow goes along such 3-arc paths;
  // pushing it in one linear pass saves the tree growth/adoption work of one augmentation each.
  for (std::int32_t u = 0; u < n; ++u) {
    for (std::int32_t a = nodes_[u].first; a < nodes_[u + 1].first && nodes_[u].tr > 0.0; ++a) {
      const std::int32_t v = arcs_[a].head;
      if (!(nodes_[v].tr < 0.0) || !(arcs_[a].rcap > 0.0)) continue;
      const double f = std::min({nodes_[u].tr, -nodes_[v].tr, arcs_[a].rcap});
      arcs_[a].rcap -= f;
      arcs_[arcs_[a].sister].rcap += f;
      nodes_[u].tr -= f;
      nodes_[v].tr += f;
    }
  }
}

// Both search trees from scratch: every node with excess (source tree) or deficit (sink tree) is
// a root at distance 1.
void MaxFlow::ResetTrees() {
  for (std::int32_t v = 0; v < n_; ++v) {
    Node& x = nodes_[v];
    x.parent = kFree;
    x.sink = 0;
    x.ts = 0;
    x.dist = 0;
    x.next = kNotQueued;
  }
  queue_first_ = queue_last_ = kQueueEnd;
  orphans_.clear();
  orphan_head_ = 0;
  time_ = 0;
  for (std::int32_t v = 0; v < n_; ++v) {
    if (nodes_[v].tr == 0.0) continue;
    nodes_[v].parent = kTerminal;
    nodes_[v].sink = nodes_[v].tr < 0.0 ? 1 : 0;
    nodes_[v].dist = 1;
    Activate(v);
  }
}

// Growth from active node i: claims free neighbours for i's tree and shortens their paths where i
// offers a shorter one; returns the arc (oriented source tree -> sink tree) where the trees meet,
// or -1 when i is exhausted.
std::int32_t MaxFlow::GrowFrom(std::int32_t i) {
  const bool sink = nodes_[i].sink;
  for (std::int32_t a = nodes_[i].first; a < nodes_[i + 1].first; ++a) {
    ++work_;
    // The residual direction the tree grows along: away from the source, or toward the sink.
    if (!((sink ? arcs_[arcs_[a].sister].rcap : arcs_[a].rcap) > 0.0)) continue;
    const std::int32_t j = arcs_[a].head;
    if (nodes_[j].parent == kFree) {
      nodes_[j].sink = sink ? 1 : 0;
      nodes_[j].parent = arcs_[a].sister;
      nodes_[j].ts = nodes_[i].ts;
      nodes_[j].dist = nodes_[i].dist + 1;
      Activate(j);
    } else if (static_cast<bool>(nodes_[j].sink) != sink) {
      return sink ? arcs_[a].sister : a;
    } else if (nodes_[j].ts <= nodes_[i].ts && nodes_[j].dist > nodes_[i].dist) {
      nodes_[j].parent = arcs_[a].sister;  // shorter path to the root through i
      nodes_[j].ts = nodes_[i].ts;
      nodes_[j].dist = nodes_[i].dist + 1;
    }
  }
  return -1;
}

bool MaxFlow::BoykovKolmogorov(std::int64_t max_work) {
  ResetTrees();
  std::int32_t current = kQueueEnd;
  while (true) {
    if (current == kQueueEnd || nodes_[current].parent == kFree) {
      current = NextActive();
      if (current == kQueueEnd) break;
    }
    const std::int32_t middle = GrowFrom(current);
    if (middle < 0) {
      current = kQueueEnd;  // exhausted until something re-activates it
      continue;
    }
    ++time_;
    Augment(middle);
    Adopt();
    if (max_work >= 0 && work_ > max_work) return false;
    // current stays: it may touch the other tree again through another arc.
  }
  return true;
}

double MaxFlow::CutValue() const {
  // From the capacities as given (not the flow pushed), so both algorithms report the same number
  // for the same cut and the exact solver's "no gain" test compares like with like.
  // Per node: its terminal term, and its CSR edges' (fixed blocks: the same double on any number
  // of threads, BlockSum2); then the AddEdge edges in order.
  double cut = constant_ + BlockSum2(n_, [&](std::int64_t u, double& terminal, double& edges) {
    const bool su = SourceSide(static_cast<std::int32_t>(u));
    const double t = user_tr_[u];
    if (su ? t < 0.0 : t > 0.0) terminal += t < 0.0 ? -t : t;
    if (!csr_) return;
    for (std::int64_t e = csr_->first[u]; e < csr_->first[u + 1]; ++e) {
      const bool sv = SourceSide(csr_->adj[e]);
      if (su && !sv) edges += csr_->forward[e];
      else if (!su && sv) edges += csr_->reverse[e];
    }
  });
  for (std::size_t e = 0; e < eu_.size(); ++e) {
    const bool su = SourceSide(eu_[e]), sv = SourceSide(ev_[e]);
    if (su && !sv) cut += ecap_uv_[e];
    else if (!su && sv) cut += ecap_vu_[e];
  }
  return cut;
}

}  // namespace al
