// Generated refinement problems for solver tests and benchmarks (CUT_PURSUIT.md §10 setup): uniform
// points in the unit cube, symmetrised exact kNN graph (grid search), each undirected edge stored
// once at its smaller endpoint, y "soft" (p = 0.75 inside a ball, 0.25 outside, +-0.25 noise) or
// "one-hot" (a binary draw from that p).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "al/graph/problem.hpp"

namespace al::cp {

inline RefineProblem MakeKnnProblem(std::int32_t n, int k, double edge_weight, double s, bool one_hot,
                                    std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<std::array<double, 3>> pts(n);
  for (auto& p : pts) p = {uni(rng), uni(rng), uni(rng)};
  // Grid with about 4 points per cell; rings grow until the k-th distance is certified.
  const int g = std::max(1, static_cast<int>(std::cbrt(n / 4.0)));
  const double h = 1.0 / g;
  auto cell_of = [&](double x) { return std::min(g - 1, static_cast<int>(x * g)); };
  std::vector<std::int32_t> cell_first(static_cast<std::size_t>(g) * g * g + 1, 0), cell_pts(n);
  auto cid = [&](int x, int y, int z) { return (static_cast<std::size_t>(x) * g + y) * g + z; };
  for (const auto& p : pts) ++cell_first[cid(cell_of(p[0]), cell_of(p[1]), cell_of(p[2])) + 1];
  for (std::size_t c = 0; c + 1 < cell_first.size(); ++c) cell_first[c + 1] += cell_first[c];
  {
    std::vector<std::int32_t> pos(cell_first.begin(), cell_first.end() - 1);
    for (std::int32_t i = 0; i < n; ++i) cell_pts[pos[cid(cell_of(pts[i][0]), cell_of(pts[i][1]), cell_of(pts[i][2]))]++] = i;
  }
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  std::vector<std::pair<double, std::int32_t>> cand;
  const int kk = std::min<std::int64_t>(k, n - 1);
  for (std::int32_t i = 0; i < n && kk > 0; ++i) {
    const int cx = cell_of(pts[i][0]), cy = cell_of(pts[i][1]), cz = cell_of(pts[i][2]);
    for (int R = 1;; ++R) {
      cand.clear();
      for (int x = std::max(0, cx - R); x <= std::min(g - 1, cx + R); ++x)
        for (int y = std::max(0, cy - R); y <= std::min(g - 1, cy + R); ++y)
          for (int z = std::max(0, cz - R); z <= std::min(g - 1, cz + R); ++z)
            for (std::int32_t a = cell_first[cid(x, y, z)]; a < cell_first[cid(x, y, z) + 1]; ++a) {
              const std::int32_t j = cell_pts[a];
              if (j == i) continue;
              double d2 = 0.0;
              for (int t = 0; t < 3; ++t) d2 += (pts[i][t] - pts[j][t]) * (pts[i][t] - pts[j][t]);
              cand.emplace_back(d2, j);
            }
      if (static_cast<int>(cand.size()) >= kk) {
        std::nth_element(cand.begin(), cand.begin() + (kk - 1), cand.end());
        const double reach = R * h;
        if (cand[kk - 1].first <= reach * reach || R >= g) {
          std::sort(cand.begin(), cand.begin() + kk);
          for (int t = 0; t < kk; ++t) edges.emplace_back(std::min(i, cand[t].second), std::max(i, cand[t].second));
          break;
        }
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  RefineProblem pb;
  pb.kl_smoothing = s;
  pb.first_edge.assign(n + 1, 0);
  for (const auto& e : edges) ++pb.first_edge[e.first + 1];
  for (std::int32_t i = 0; i < n; ++i) pb.first_edge[i + 1] += pb.first_edge[i];
  for (const auto& e : edges) pb.adj_vertices.push_back(e.second);
  pb.edge_weights.assign(edges.size(), edge_weight);
  pb.node_weights.assign(n, 1.0);
  pb.y_remove.resize(n);
  pb.node_ids.resize(n);
  for (std::int32_t i = 0; i < n; ++i) {
    double r2 = 0.0;
    for (int t = 0; t < 3; ++t) r2 += (pts[i][t] - 0.5) * (pts[i][t] - 0.5);
    double p = (r2 < 0.3 * 0.3 ? 0.75 : 0.25) + 0.5 * (uni(rng) - 0.5);
    p = std::clamp(p, 0.0, 1.0);
    pb.y_remove[i] = one_hot ? (uni(rng) < p ? 1.0 : 0.0) : p;
    pb.node_ids[i] = i;
  }
  return pb;
}

}  // namespace al::cp
