// A small s-t minimum cut (Dinic's blocking flows, iterative DFS) for the cut-pursuit split and the
// exact level-set solver. Written for this project (the GPL max-flow codes of pcp / Kolmogorov are
// not used). Conventions of CUT_PURSUIT.md §4.4: a signed unary a_v is a source->v arc of capacity a
// (a > 0) or a v->sink arc of capacity -a (a < 0); after Solve(), nodes on the SINK side are those
// that pay a_v, i.e. take the "new" label / lie "above" the level.
#pragma once
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace al::cp {

class MinCut {
 public:
  explicit MinCut(std::int32_t num_nodes) : n_(num_nodes), unary_(num_nodes, 0.0) {}

  void AddUnary(std::int32_t v, double a) { unary_[v] += a; }
  // Edge with capacity cap_uv from u to v and cap_vu from v to u (both >= 0).
  void AddEdge(std::int32_t u, std::int32_t v, double cap_uv, double cap_vu) {
    if (!(cap_uv > 0.0) && !(cap_vu > 0.0)) return;
    pending_.push_back({u, v, cap_uv, cap_vu});
  }

  // Runs the max-flow; returns the flow value (cut cost minus the constant of negative unaries).
  double Solve() {
    Build();
    const std::int32_t s = n_, t = n_ + 1;
    double total = 0.0;
    std::vector<std::int32_t> level(n_ + 2), queue(n_ + 2), it(n_ + 2);
    std::vector<std::int32_t> path;  // arcs of the current DFS path
    while (true) {
      // BFS levels from the source over arcs with residual capacity.
      std::fill(level.begin(), level.end(), -1);
      std::int32_t head = 0, tail = 0;
      queue[tail++] = s;
      level[s] = 0;
      while (head < tail) {
        const std::int32_t u = queue[head++];
        for (std::int32_t a = first_[u]; a < first_[u + 1]; ++a)
          if (cap_[a] > 0.0 && level[to_[a]] < 0) {
            level[to_[a]] = level[u] + 1;
            queue[tail++] = to_[a];
          }
      }
      if (level[t] < 0) break;
      for (std::int32_t u = 0; u < n_ + 2; ++u) it[u] = first_[u];
      // Blocking flow by iterative DFS with current-arc pointers.
      path.clear();
      std::int32_t u = s;
      while (true) {
        if (u == t) {
          double f = std::numeric_limits<double>::infinity();
          for (std::int32_t a : path) f = std::min(f, cap_[a]);
          std::size_t cut_at = path.size();
          for (std::size_t i = 0; i < path.size(); ++i) {
            const std::int32_t a = path[i];
            cap_[a] -= f;
            cap_[rev_[a]] += f;
            if (cut_at == path.size() && !(cap_[a] > 0.0)) cut_at = i;
          }
          total += f;
          path.resize(cut_at);
          u = path.empty() ? s : to_[path.back()];
          continue;
        }
        bool advanced = false;
        for (std::int32_t& a = it[u]; a < first_[u + 1]; ++a) {
          const std::int32_t v = to_[a];
          if (cap_[a] > 0.0 && level[v] == level[u] + 1) {
            path.push_back(a);
            u = v;
            advanced = true;
            break;
          }
        }
        if (advanced) continue;
        if (u == s) break;
        level[u] = -1;  // dead end in this phase
        path.pop_back();
        u = path.empty() ? s : to_[path.back()];
        ++it[u];
      }
    }
    // Source side = reachable from the source in the residual graph.
    side_.assign(n_, 1);
    std::vector<char> seen(n_ + 2, 0);
    std::int32_t head = 0, tail = 0;
    queue[tail++] = s;
    seen[s] = 1;
    while (head < tail) {
      const std::int32_t x = queue[head++];
      for (std::int32_t a = first_[x]; a < first_[x + 1]; ++a)
        if (cap_[a] > 0.0 && !seen[to_[a]]) {
          seen[to_[a]] = 1;
          queue[tail++] = to_[a];
        }
    }
    for (std::int32_t v = 0; v < n_; ++v) side_[v] = seen[v] ? 0 : 1;
    return total;
  }

  // 1 if v ended on the sink side (takes the new label / lies above), 0 otherwise.
  bool IsSink(std::int32_t v) const { return side_[v] != 0; }

 private:
  struct Pending {
    std::int32_t u, v;
    double cuv, cvu;
  };

  void Build() {
    const std::int32_t s = n_, t = n_ + 1, N = n_ + 2;
    std::vector<std::int32_t> degree(N + 1, 0);
    for (std::int32_t v = 0; v < n_; ++v)
      if (unary_[v] != 0.0) {
        ++degree[v];
        ++degree[unary_[v] > 0.0 ? s : t];
      }
    for (const Pending& p : pending_) {
      ++degree[p.u];
      ++degree[p.v];
    }
    first_.assign(N + 1, 0);
    for (std::int32_t i = 0; i < N; ++i) first_[i + 1] = first_[i] + degree[i];
    const std::int32_t arcs = first_[N];
    to_.assign(arcs, 0);
    rev_.assign(arcs, 0);
    cap_.assign(arcs, 0.0);
    std::vector<std::int32_t> pos(first_.begin(), first_.end() - 1);
    auto add = [&](std::int32_t a, std::int32_t b, double cab, double cba) {
      const std::int32_t i = pos[a]++, j = pos[b]++;
      to_[i] = b;
      cap_[i] = cab;
      rev_[i] = j;
      to_[j] = a;
      cap_[j] = cba;
      rev_[j] = i;
    };
    for (std::int32_t v = 0; v < n_; ++v) {
      if (unary_[v] > 0.0) add(s, v, unary_[v], 0.0);
      else if (unary_[v] < 0.0) add(v, t, -unary_[v], 0.0);
    }
    for (const Pending& p : pending_) add(p.u, p.v, p.cuv, p.cvu);
  }

  std::int32_t n_;
  std::vector<double> unary_;
  std::vector<Pending> pending_;
  std::vector<std::int32_t> first_, to_, rev_;
  std::vector<double> cap_;
  std::vector<char> side_;
};

}  // namespace al::cp
