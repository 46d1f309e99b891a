// Boykov-Kolmogorov max-flow (see max_flow.hpp). Two search trees grow from the terminals over
// non-saturated arcs; when they touch, the path is augmented, saturated tree arcs turn their child
// into an orphan, and orphans try to re-attach to a node of their own tree whose root path is still
// valid ("adoption", with timestamps/distances so validity checks stop early and prefer short paths).
// Unlike Dinic, the trees survive augmentations, which is why this is much faster on the kNN graphs
// of al-refine (few long augmenting paths, many short ones).
//
// Conventions: parent_[v] is the arc v -> parent. In the source tree flow runs parent -> v, so the
// arc that must stay non-saturated is sister_[parent_[v]]; in the sink tree it is parent_[v] itself.
#include "max_flow.hpp"

#include <algorithm>
#include <limits>

namespace al {

void MaxFlow::Reset(std::int32_t num_nodes) {
  n_ = num_nodes;
  flow_ = 0.0;
  augmentations_ = 0;
  eu_.clear();
  ev_.clear();
  ecap_uv_.clear();
  ecap_vu_.clear();
  tr_.assign(num_nodes, 0.0);
}

void MaxFlow::AddTerminal(std::int32_t v, double source_cap, double sink_cap) {
  // Only the difference needs an arc; the common part is paid by every cut.
  const double delta = tr_[v];
  if (delta > 0.0) source_cap += delta;
  else sink_cap -= delta;
  flow_ += std::min(source_cap, sink_cap);
  tr_[v] = source_cap - sink_cap;
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
  first_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (std::size_t e = 0; e < m; ++e) {
    ++first_[eu_[e] + 1];
    ++first_[ev_[e] + 1];
  }
  for (std::int32_t v = 0; v < n; ++v) first_[v + 1] += first_[v];
  head_.resize(2 * m);
  sister_.resize(2 * m);
  rcap_.resize(2 * m);
  // Fill with a moving cursor per node (borrowing next_ as scratch), in insertion order.
  next_.assign(first_.begin(), first_.end() - 1);
  for (std::size_t e = 0; e < m; ++e) {
    const std::int32_t i = next_[eu_[e]]++, j = next_[ev_[e]]++;
    head_[i] = ev_[e];
    head_[j] = eu_[e];
    sister_[i] = j;
    sister_[j] = i;
    rcap_[i] = ecap_uv_[e];
    rcap_[j] = ecap_vu_[e];
  }
}

void MaxFlow::Activate(std::int32_t v) {
  if (next_[v] != kNotQueued) return;
  next_[v] = kQueueEnd;
  if (queue_last_ != kQueueEnd) next_[queue_last_] = v;
  else queue_first_ = v;
  queue_last_ = v;
}

std::int32_t MaxFlow::NextActive() {
  while (queue_first_ != kQueueEnd) {
    const std::int32_t v = queue_first_;
    queue_first_ = next_[v];
    if (queue_first_ == kQueueEnd) queue_last_ = kQueueEnd;
    next_[v] = kNotQueued;
    if (parent_[v] != kFree) return v;  // freed nodes stay in the queue lazily
  }
  return kQueueEnd;
}

void MaxFlow::MakeOrphan(std::int32_t v) {
  parent_[v] = kOrphan;
  orphans_.push_back(v);
}

void MaxFlow::Augment(std::int32_t middle) {
  // middle goes from the source tree (head of its sister) to the sink tree (its head).
  const std::int32_t s_end = head_[sister_[middle]], t_end = head_[middle];
  double f = rcap_[middle];
  std::int32_t v = s_end;
  for (std::int32_t a; (a = parent_[v]) != kTerminal; v = head_[a]) f = std::min(f, rcap_[sister_[a]]);
  f = std::min(f, tr_[v]);
  v = t_end;
  for (std::int32_t a; (a = parent_[v]) != kTerminal; v = head_[a]) f = std::min(f, rcap_[a]);
  f = std::min(f, -tr_[v]);

  rcap_[middle] -= f;
  rcap_[sister_[middle]] += f;
  for (v = s_end;;) {
    const std::int32_t a = parent_[v];
    if (a == kTerminal) {
      tr_[v] -= f;
      if (!(tr_[v] > 0.0)) MakeOrphan(v);
      break;
    }
    const std::int32_t up = head_[a];
    rcap_[a] += f;
    rcap_[sister_[a]] -= f;
    if (!(rcap_[sister_[a]] > 0.0)) MakeOrphan(v);
    v = up;
  }
  for (v = t_end;;) {
    const std::int32_t a = parent_[v];
    if (a == kTerminal) {
      tr_[v] += f;
      if (!(tr_[v] < 0.0)) MakeOrphan(v);
      break;
    }
    const std::int32_t up = head_[a];
    rcap_[sister_[a]] += f;
    rcap_[a] -= f;
    if (!(rcap_[a] > 0.0)) MakeOrphan(v);
    v = up;
  }
  flow_ += f;
  ++augmentations_;
}

void MaxFlow::ProcessOrphan(std::int32_t v) {
  const bool sink = sink_tree_[v] != 0;
  constexpr std::int32_t kInfDist = std::numeric_limits<std::int32_t>::max();
  std::int32_t best_arc = kFree, best_dist = kInfDist;
  for (std::int32_t a0 = first_[v]; a0 < first_[v + 1]; ++a0) {
    // The arc that would carry flow between v and the candidate parent j must be non-saturated.
    if (!((sink ? rcap_[a0] : rcap_[sister_[a0]]) > 0.0)) continue;
    const std::int32_t j = head_[a0];
    if ((sink_tree_[j] != 0) != sink || parent_[j] == kFree) continue;
    // Is j's root path still valid (ends at the terminal without meeting an orphan)?
    std::int32_t d = 0, k = j;
    while (true) {
      if (ts_[k] == time_) { d += dist_[k]; break; }
      const std::int32_t a = parent_[k];
      ++d;
      if (a == kTerminal) { ts_[k] = time_; dist_[k] = 1; break; }
      if (a == kOrphan) { d = kInfDist; break; }
      k = head_[a];
    }
    if (d == kInfDist) continue;
    if (d < best_dist) { best_arc = a0; best_dist = d; }
    for (k = j; ts_[k] != time_; k = head_[parent_[k]]) {  // remember the checked path
      ts_[k] = time_;
      dist_[k] = d--;
    }
  }
  if (best_arc != kFree) {
    parent_[v] = best_arc;
    ts_[v] = time_;
    dist_[v] = best_dist + 1;
    return;
  }
  // No valid parent: v becomes free; its children become orphans, neighbours that could reach it
  // again become active.
  parent_[v] = kFree;
  for (std::int32_t a0 = first_[v]; a0 < first_[v + 1]; ++a0) {
    const std::int32_t j = head_[a0];
    const std::int32_t pj = parent_[j];
    if ((sink_tree_[j] != 0) != sink || pj == kFree) continue;
    if ((sink ? rcap_[a0] : rcap_[sister_[a0]]) > 0.0) Activate(j);
    if (pj != kTerminal && pj != kOrphan && head_[pj] == v) MakeOrphan(j);
  }
}

void MaxFlow::Adopt() {
  while (orphan_head_ < orphans_.size()) ProcessOrphan(orphans_[orphan_head_++]);
  orphans_.clear();
  orphan_head_ = 0;
}

double MaxFlow::Solve() {
  const std::int32_t n = n_;
  Build();
  parent_.assign(n, kFree);
  sink_tree_.assign(n, 0);
  ts_.assign(n, 0);
  dist_.assign(n, 0);
  next_.assign(n, kNotQueued);
  queue_first_ = queue_last_ = kQueueEnd;
  orphans_.clear();
  orphan_head_ = 0;
  time_ = 0;
  // Greedy pre-flow over source-node -> sink-node arcs. When unaries dominate the edge capacities
  // (typical for cut pursuit splits and level cuts) most of the flow goes along such 3-arc paths;
  // pushing it in one linear pass saves the tree growth/adoption work of one augmentation each.
  for (std::int32_t u = 0; u < n; ++u) {
    for (std::int32_t a = first_[u]; a < first_[u + 1] && tr_[u] > 0.0; ++a) {
      const std::int32_t v = head_[a];
      if (!(tr_[v] < 0.0) || !(rcap_[a] > 0.0)) continue;
      const double f = std::min({tr_[u], -tr_[v], rcap_[a]});
      rcap_[a] -= f;
      rcap_[sister_[a]] += f;
      tr_[u] -= f;
      tr_[v] += f;
      flow_ += f;
    }
  }
  for (std::int32_t v = 0; v < n; ++v) {
    if (tr_[v] == 0.0) continue;
    parent_[v] = kTerminal;
    sink_tree_[v] = tr_[v] < 0.0 ? 1 : 0;
    dist_[v] = 1;
    Activate(v);
  }
  std::int32_t current = kQueueEnd;
  while (true) {
    if (current == kQueueEnd || parent_[current] == kFree) {
      current = NextActive();
      if (current == kQueueEnd) break;
    }
    const std::int32_t i = current;
    std::int32_t middle = -1;
    // Growth: claim free neighbours; a neighbour of the other tree closes a path.
    if (!sink_tree_[i]) {
      for (std::int32_t a = first_[i]; a < first_[i + 1]; ++a) {
        if (!(rcap_[a] > 0.0)) continue;
        const std::int32_t j = head_[a];
        if (parent_[j] == kFree) {
          sink_tree_[j] = 0;
          parent_[j] = sister_[a];
          ts_[j] = ts_[i];
          dist_[j] = dist_[i] + 1;
          Activate(j);
        } else if (sink_tree_[j]) {
          middle = a;
          break;
        } else if (ts_[j] <= ts_[i] && dist_[j] > dist_[i]) {
          parent_[j] = sister_[a];  // shorter path to the source through i
          ts_[j] = ts_[i];
          dist_[j] = dist_[i] + 1;
        }
      }
    } else {
      for (std::int32_t a = first_[i]; a < first_[i + 1]; ++a) {
        if (!(rcap_[sister_[a]] > 0.0)) continue;
        const std::int32_t j = head_[a];
        if (parent_[j] == kFree) {
          sink_tree_[j] = 1;
          parent_[j] = sister_[a];
          ts_[j] = ts_[i];
          dist_[j] = dist_[i] + 1;
          Activate(j);
        } else if (!sink_tree_[j]) {
          middle = sister_[a];
          break;
        } else if (ts_[j] <= ts_[i] && dist_[j] > dist_[i]) {
          parent_[j] = sister_[a];
          ts_[j] = ts_[i];
          dist_[j] = dist_[i] + 1;
        }
      }
    }
    if (middle < 0) {
      current = kQueueEnd;  // i is exhausted until something re-activates it
      continue;
    }
    ++time_;
    Augment(middle);
    Adopt();
    // i stays current: it may touch the other tree again through another arc.
  }
  return flow_;
}

}  // namespace al
