// Phase 1 of MaxFlow::Solve (max_flow.hpp): Hochbaum's highest-label pseudoflow algorithm
// (D. S. Hochbaum, "The pseudoflow algorithm: a new algorithm for the maximum-flow problem",
// Operations Research 56(4), 2008), written for this project from the paper.
//
// Every terminal arc starts saturated, so a node holds an excess (tr > 0) or a deficit (tr < 0).
// Nodes form a forest in which only roots carry excess; a tree is "strong" if its root's excess is
// positive. The strong root of highest label is processed: a depth-first search over the nodes of its
// tree that share the root's label l looks for a residual arc to a node of label l - 1 (a "merger").
// The tree is then re-rooted at the merging node, hung below the other end, and the root's excess is
// pushed along the tree path to the new root; where an arc cannot take it all, the arc is saturated,
// the tree is split there and the part below becomes a strong root of its own. Nodes whose search
// fails are relabelled l + 1 bottom-up. If no node has label l - 1 (a gap), the whole tree can no
// longer reach a deficit and is lifted to the dead label n.
//
// Invariants the search relies on: (1) valid labels, label(u) <= label(v) + 1 for every residual arc
// u -> v; (2) within a tree a child's label is >= its parent's, so a merger target (label l - 1) is
// never in the searched tree and merging cannot create a cycle; (3) deficit roots keep label 0, so a
// gap above 0 proves that no deficit is reachable. Each node keeps a current arc (next_arc): arcs
// before it are known to lead nowhere at the node's current label and are not scanned again until
// the node is relabelled (an arc a split hands back cannot be a merger before that: see
// MergeAndPush).
//
// Nothing here needs to be exact: the Boykov-Kolmogorov phase that follows starts from the resulting
// pseudoflow (valid at every step: capacities are never exceeded) and augments whatever is left, and
// it is what defines the returned cut.
#include <algorithm>

#include "solvers/max_flow/max_flow.hpp"

namespace al {

void MaxFlow::TreeLink(std::int32_t child, std::int32_t parent, std::int32_t arc) {
  TreeNode& c = tree_[child];
  c.parent = parent;
  c.parent_arc = arc;
  c.prev_sibling = -1;
  c.next_sibling = tree_[parent].first_child;
  if (c.next_sibling >= 0) tree_[c.next_sibling].prev_sibling = child;
  tree_[parent].first_child = child;
}

void MaxFlow::TreeUnlink(std::int32_t child) {
  TreeNode& c = tree_[child];
  TreeNode& p = tree_[c.parent];
  if (c.prev_sibling >= 0) tree_[c.prev_sibling].next_sibling = c.next_sibling;
  else p.first_child = c.next_sibling;
  if (c.next_sibling >= 0) tree_[c.next_sibling].prev_sibling = c.prev_sibling;
  if (p.next_scan == child) p.next_scan = c.next_sibling;  // keep a pending search position valid
  c.parent = -1;
  c.prev_sibling = c.next_sibling = -1;
}

void MaxFlow::BucketAdd(std::int32_t root) {
  const std::int32_t l = tree_[root].label;
  tree_[root].bucket_next = -1;
  if (bucket_last_[l] >= 0) tree_[bucket_last_[l]].bucket_next = root;
  else bucket_first_[l] = root;
  bucket_last_[l] = root;
}

std::int32_t MaxFlow::BucketPop(std::int32_t label) {
  const std::int32_t root = bucket_first_[label];
  bucket_first_[label] = tree_[root].bucket_next;
  if (bucket_first_[label] < 0) bucket_last_[label] = -1;
  return root;
}

// Sets the label of the nodes of root's tree to `to`: all of them (only_label < 0), or those with
// label only_label reached through such nodes (by invariant 2 they form the top of the tree).
void MaxFlow::SetLabels(std::int32_t root, std::int32_t only_label, std::int32_t to) {
  stack_.assign(1, root);
  while (!stack_.empty()) {
    const std::int32_t v = stack_.back();
    stack_.pop_back();
    --label_count_[tree_[v].label];
    tree_[v].label = to;
    ++label_count_[to];
    tree_[v].next_arc = nodes_[v].first;
    for (std::int32_t c = tree_[v].first_child; c >= 0; c = tree_[c].next_sibling)
      if (only_label < 0 || tree_[c].label == only_label) stack_.push_back(c);
  }
}

std::int32_t MaxFlow::HighestStrongRoot() {
  for (std::int32_t l = highest_; l >= 1; --l) {
    while (bucket_first_[l] >= 0) {
      highest_ = l;
      const std::int32_t root = BucketPop(l);
      if (label_count_[l - 1] > 0) return root;
      ++stats_.gap_lifts;
      SetLabels(root, -1, n_);
    }
  }
  if (bucket_first_[0] < 0) return -1;
  // Strong roots of label 0 (a deficit tree that received more than it lacked): lift the label-0 top
  // of each tree together, which keeps invariant 2 (lifting 0 -> 1 never breaks invariant 1).
  while (bucket_first_[0] >= 0) {
    const std::int32_t root = BucketPop(0);
    SetLabels(root, 0, 1);
    BucketAdd(root);
  }
  highest_ = 1;
  return HighestStrongRoot();  // bucket 0 is empty now: one more pass applies the gap test at 1
}

std::int32_t MaxFlow::FindMerger(std::int32_t v, std::int32_t label) {
  const std::int32_t end = nodes_[v + 1].first;
  for (std::int32_t a = tree_[v].next_arc; a < end; ++a) {
    const std::int32_t w = arcs_[a].head;
    if (tree_[w].label != label - 1 || !(arcs_[a].rcap > 0.0)) continue;
    // Tree neighbours never have label - 1 (invariant 2); the test only guards against a cycle.
    if (tree_[v].parent == w || tree_[w].parent == v) continue;
    tree_[v].next_arc = a;
    return a;
  }
  tree_[v].next_arc = end;
  return -1;
}

// Advances v's search position past children that already left `label`; when none is left, v's
// subtree holds no merger at this label and v moves to label + 1.
void MaxFlow::RelabelIfDone(std::int32_t v, std::int32_t label) {
  TreeNode& x = tree_[v];
  for (; x.next_scan >= 0; x.next_scan = tree_[x.next_scan].next_sibling)
    if (tree_[x.next_scan].label == label) return;
  --label_count_[label];
  ++x.label;
  ++label_count_[x.label];
  x.next_arc = nodes_[v].first;
  ++stats_.relabels;
}

void MaxFlow::MergeAndPush(std::int32_t strong_node, std::int32_t arc, std::int32_t root) {
  ++stats_.mergers;
  // Re-root the strong tree at strong_node (reversing the path up to root) and hang it below the
  // arc's head.
  std::int32_t cur = strong_node, new_parent = arcs_[arc].head, new_arc = arc;
  while (tree_[cur].parent >= 0) {
    const std::int32_t old_parent = tree_[cur].parent, old_arc = tree_[cur].parent_arc;
    TreeUnlink(cur);
    TreeLink(cur, new_parent, new_arc);
    new_parent = cur;
    new_arc = arcs_[old_arc].sister;
    cur = old_parent;
  }
  TreeLink(cur, new_parent, new_arc);
  // Push the old root's excess towards the new root; split below every arc that saturates.
  cur = root;
  double before = 1.0;  // excess of the last node pushed into, before the push
  while (nodes_[cur].tr > 0.0 && tree_[cur].parent >= 0) {
    const std::int32_t p = tree_[cur].parent, a = tree_[cur].parent_arc, b = arcs_[a].sister;
    before = nodes_[p].tr;
    const double excess = nodes_[cur].tr, room = arcs_[a].rcap;
    if (room >= excess) {
      arcs_[a].rcap = room - excess;
      arcs_[b].rcap += excess;
      nodes_[p].tr += excess;
      nodes_[cur].tr = 0.0;
    } else {
      arcs_[a].rcap = 0.0;
      arcs_[b].rcap += room;
      nodes_[p].tr += room;
      nodes_[cur].tr = excess - room;
      // p can push back to cur now, but cur's label is >= p's (invariant 2), so the arc cannot be a
      // merger before p is relabelled, which rescans all of p's arcs: p's current arc stays valid.
      TreeUnlink(cur);
      BucketAdd(cur);
    }
    cur = p;
  }
  // A root that was not strong before and now holds excess becomes a strong root.
  if (tree_[cur].parent < 0 && nodes_[cur].tr > 0.0 && !(before > 0.0)) BucketAdd(cur);
}

void MaxFlow::ProcessRoot(std::int32_t root) {
  const std::int32_t label = tree_[root].label;
  tree_[root].next_scan = tree_[root].first_child;
  if (const std::int32_t a = FindMerger(root, label); a >= 0) return MergeAndPush(root, a, root);
  RelabelIfDone(root, label);
  // Depth-first over the label-l part of the tree; a node is relabelled once all its label-l
  // children are (so children never end below their parent: invariant 2).
  std::int32_t v = root;
  while (v >= 0) {
    while (tree_[v].next_scan >= 0) {
      const std::int32_t c = tree_[v].next_scan;
      tree_[v].next_scan = tree_[c].next_sibling;
      v = c;
      tree_[v].next_scan = tree_[v].first_child;
      if (const std::int32_t a = FindMerger(v, label); a >= 0) return MergeAndPush(v, a, root);
      RelabelIfDone(v, label);
    }
    v = tree_[v].parent;
    if (v >= 0) RelabelIfDone(v, label);
  }
  if (tree_[root].label >= n_) {  // labels beyond n - 1 carry no information: dead
    SetLabels(root, -1, n_);
    return;
  }
  BucketAdd(root);
  highest_ = std::max(highest_, tree_[root].label);
}

void MaxFlow::Pseudoflow() {
  const std::int32_t n = n_;
  if (n == 0) return;
  tree_.resize(n);
  bucket_first_.assign(static_cast<std::size_t>(n) + 1, -1);
  bucket_last_.assign(static_cast<std::size_t>(n) + 1, -1);
  label_count_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (std::int32_t v = 0; v < n; ++v) {
    TreeNode& x = tree_[v];
    x.label = nodes_[v].tr > 0.0 ? 1 : 0;
    x.parent = x.parent_arc = x.first_child = x.next_sibling = x.prev_sibling = x.next_scan = -1;
    x.next_arc = nodes_[v].first;
    ++label_count_[x.label];
    if (x.label == 1) BucketAdd(v);
  }
  highest_ = 1;
  // A safety valve, not a tuning knob: the algorithm terminates on its own, but should rounding ever
  // keep it busy, BK takes over from the (always valid) pseudoflow and the cut stays exact.
  const std::int64_t budget =
      100 * (static_cast<std::int64_t>(n) + static_cast<std::int64_t>(arcs_.size())) + 1000000;
  for (std::int32_t root; (root = HighestStrongRoot()) >= 0;) {
    ProcessRoot(root);
    if (stats_.mergers + stats_.relabels > budget) {
      stats_.budget_exhausted = true;
      break;
    }
  }
}

}  // namespace al
