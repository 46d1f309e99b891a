// FLANN kNN with deterministic tie-breaking (see knn.hpp).
#include "al/graph/knn.hpp"

#include "al/core/option_table.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include <flann/flann.hpp>

#include "al/core/timer.hpp"

namespace al {
namespace {

std::uint64_t Spread3(std::uint64_t v) {  // 21 bits -> every third bit
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

struct Entry {
  float d;
  std::int32_t i;
};

// One query: sorted (dist, index) list of the `want` nearest points other than `self`.
template <class Index>
void Query(const Index& index, const float* q, std::int32_t self, int k, std::size_t n,
           const flann::SearchParams& params, std::vector<Entry>& out, std::size_t& retries) {
  std::size_t m = std::min<std::size_t>(n, static_cast<std::size_t>(k) + 1 + 8);
  std::vector<std::size_t> idx;
  std::vector<float> dist;
  for (;;) {
    flann::KNNSimpleResultSet<float> rs(m);
    index.findNeighbors(rs, q, params);
    const std::size_t got = rs.size();
    idx.resize(got);
    dist.resize(got);
    if (got > 0) rs.copy(idx.data(), dist.data(), got);
    out.clear();
    for (std::size_t t = 0; t < got; ++t)
      if (static_cast<std::int32_t>(idx[t]) != self)
        out.push_back({dist[t], static_cast<std::int32_t>(idx[t])});
    std::sort(out.begin(), out.end(),
              [](const Entry& a, const Entry& b) { return a.d < b.d || (a.d == b.d && a.i < b.i); });
    // Complete when every point was returned, or the k-th kept neighbour is strictly closer
    // than the farthest returned point (so no unseen point can tie with it).
    const bool all = got >= n || got < m;
    if (all || (out.size() >= static_cast<std::size_t>(k) && out[k - 1].d < dist[got - 1])) break;
    m = std::min(n, 2 * m);
    ++retries;
  }
  if (out.size() > static_cast<std::size_t>(k)) out.resize(k);
}

// Exactly coincident points (same coordinates) as groups: points[begin[g]..begin[g+1]) are the
// members of group g in ascending index; rep[g] is its first member. Empty when all are distinct.
struct Groups {
  std::vector<std::int32_t> group_of, members, begin, rep;
};

Groups GroupCoincident(std::span<const float> xyz) {
  const std::size_t n = xyz.size() / 3;
  auto key = [&](std::int32_t i) {
    std::array<std::uint32_t, 3> k;
    std::memcpy(k.data(), &xyz[3 * std::size_t(i)], sizeof k);
    return k;
  };
  std::vector<std::int32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::int32_t>(i);
  std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    const auto ka = key(a), kb = key(b);
    return ka != kb ? ka < kb : a < b;
  });
  Groups g;
  g.group_of.assign(n, -1);
  for (std::size_t t = 0; t < n; ++t) {
    if (t == 0 || key(order[t]) != key(order[t - 1])) g.begin.push_back(static_cast<std::int32_t>(t));
    g.group_of[order[t]] = static_cast<std::int32_t>(g.begin.size() - 1);
  }
  if (g.begin.size() == n) return {};
  g.begin.push_back(static_cast<std::int32_t>(n));
  g.members = std::move(order);
  // Renumber groups by their first member, so the unique-point array keeps input order.
  const std::size_t m = g.begin.size() - 1;
  std::vector<std::int32_t> by_first(m);
  for (std::size_t u = 0; u < m; ++u) by_first[u] = static_cast<std::int32_t>(u);
  std::sort(by_first.begin(), by_first.end(),
            [&](std::int32_t a, std::int32_t b) { return g.members[g.begin[a]] < g.members[g.begin[b]]; });
  std::vector<std::int32_t> rank(m), members(n), begin(m + 1, 0);
  for (std::size_t r = 0; r < m; ++r) rank[by_first[r]] = static_cast<std::int32_t>(r);
  for (std::size_t r = 0; r < m; ++r) {
    const std::int32_t u = by_first[r];
    begin[r + 1] = begin[r] + (g.begin[u + 1] - g.begin[u]);
    std::copy(g.members.begin() + g.begin[u], g.members.begin() + g.begin[u + 1], members.begin() + begin[r]);
  }
  for (auto& go : g.group_of) go = rank[go];
  g.members = std::move(members);
  g.begin = std::move(begin);
  g.rep.resize(m);
  for (std::size_t r = 0; r < m; ++r) g.rep[r] = g.members[g.begin[r]];
  return g;
}

// The k + 1 smallest (distance, index) pairs over all points, for a query at unique point u:
// its own group at distance 0, then the groups of its nearest unique points. A group contributes
// at most `want` members (its smallest indices), so a group of 100k coincident points costs O(k)
// instead of 100k per query (the tie retry would otherwise grow to the whole group).
template <class Index>
void QueryGroup(const Index& index, const float* q, std::int32_t u, std::size_t want, const Groups& g,
                const flann::SearchParams& params, std::vector<Entry>& out, std::size_t& retries) {
  const std::size_t m = g.rep.size();
  std::size_t ask = std::min<std::size_t>(m, want + 1 + 8);
  std::vector<std::size_t> idx;
  std::vector<float> dist;
  for (;;) {
    flann::KNNSimpleResultSet<float> rs(ask);
    index.findNeighbors(rs, q, params);
    const std::size_t got = rs.size();
    idx.resize(got);
    dist.resize(got);
    if (got > 0) rs.copy(idx.data(), dist.data(), got);
    out.clear();
    for (std::int32_t t = g.begin[u]; t < g.begin[u + 1] && out.size() < want; ++t) out.push_back({0.0f, g.members[t]});
    for (std::size_t t = 0; t < got; ++t) {
      const auto v = static_cast<std::int32_t>(idx[t]);
      if (v == u) continue;
      const std::int32_t end = std::min<std::int32_t>(g.begin[v + 1], g.begin[v] + std::int32_t(want));
      for (std::int32_t s = g.begin[v]; s < end; ++s) out.push_back({dist[t], g.members[s]});
    }
    std::sort(out.begin(), out.end(),
              [](const Entry& a, const Entry& b) { return a.d < b.d || (a.d == b.d && a.i < b.i); });
    const bool all = got >= m || got < ask;
    if (all || (out.size() >= want && out[want - 1].d < dist[got - 1])) break;
    ask = std::min(m, 2 * ask);
    ++retries;
  }
  if (out.size() > want) out.resize(want);
}

// KnnAmongPoints when some points coincide: one query per unique point, on a tree of unique points.
template <class Index>
void KnnGrouped(const Index& index, std::span<const float> uxyz, const Groups& g, int k,
                const flann::SearchParams& params, KnnResult& result, std::size_t& retries) {
  const auto m = static_cast<std::int64_t>(g.rep.size());
  const std::vector<std::int32_t> order = MortonOrder(uxyz);
#pragma omp parallel reduction(+ : retries)
  {
    std::vector<Entry> out;
#pragma omp for schedule(dynamic, 256)
    for (std::int64_t t = 0; t < m; ++t) {
      const std::int32_t u = order[t];
      QueryGroup(index, &uxyz[3 * std::size_t(u)], u, std::size_t(k) + 1, g, params, out, retries);
      for (std::int32_t s = g.begin[u]; s < g.begin[u + 1]; ++s) {
        const std::int32_t i = g.members[s];
        std::size_t c = 0;
        for (const Entry& e : out) {
          if (e.i == i || c == std::size_t(k)) continue;
          result.neighbors[std::size_t(i) * k + c] = e.i;
          result.sq_dist[std::size_t(i) * k + c] = e.d;
          ++c;
        }
      }
    }
  }
}

}  // namespace

std::vector<std::int32_t> MortonOrder(std::span<const float> xyz) {
  const std::size_t n = xyz.size() / 3;
  float lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::numeric_limits<float>::infinity();
    hi[a] = -lo[a];
  }
  for (std::size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], xyz[3 * i + a]);
      hi[a] = std::max(hi[a], xyz[3 * i + a]);
    }
  std::vector<std::pair<std::uint64_t, std::int32_t>> code(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t c = 0;
    for (int a = 0; a < 3; ++a) {
      const double ext = double(hi[a]) - lo[a];
      const double t = ext > 0 ? (double(xyz[3 * i + a]) - lo[a]) / ext : 0.0;
      c |= Spread3(static_cast<std::uint64_t>(t * 2097151.0)) << a;
    }
    code[i] = {c, static_cast<std::int32_t>(i)};
  }
  std::sort(code.begin(), code.end());
  std::vector<std::int32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = code[i].second;
  return order;
}

void KnnOptions::Check() const {
  CheckOptionRange("knn", "k", k, NumericRange::AtLeast(1), "neighbours per point");
  CheckOptionRange("knn", "checks", checks, NumericRange::AtLeast(0), "0 = exact; > 0 approximate (FLANN checks)");
}

KnnResult KnnAmongPoints(std::span<const float> xyz, const KnnOptions& options) {
  options.Check();
  Timer timer;
  const std::size_t n = xyz.size() / 3;
  KnnResult result;
  result.k = std::max(0, std::min<int>(options.k, static_cast<int>(n) - 1));
  const int k = result.k;
  result.neighbors.assign(n * k, -1);
  result.sq_dist.assign(n * k, 0.0f);
  if (k <= 0) {
    result.seconds = timer.Seconds();
    return result;
  }
  const Groups groups = GroupCoincident(xyz);
  if (!groups.rep.empty()) {
    result.coincident = n - groups.rep.size();
    std::vector<float> uxyz(3 * groups.rep.size());
    for (std::size_t u = 0; u < groups.rep.size(); ++u)
      std::copy_n(&xyz[3 * std::size_t(groups.rep[u])], 3, &uxyz[3 * u]);
    flann::Matrix<float> udata(uxyz.data(), groups.rep.size(), 3);
    std::size_t retries = 0;
    if (options.checks <= 0) {
      flann::KDTreeSingleIndex<flann::L2_Simple<float>> index(udata, flann::KDTreeSingleIndexParams(10));
      index.buildIndex();
      KnnGrouped(index, uxyz, groups, k, flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED, 0.0f, false), result, retries);
    } else {
      flann::seed_random(12345);
      flann::KDTreeIndex<flann::L2_Simple<float>> index(udata, flann::KDTreeIndexParams(4));
      index.buildIndex();
      KnnGrouped(index, uxyz, groups, k, flann::SearchParams(options.checks, 0.0f, false), result, retries);
    }
    result.tie_retries = retries;
    result.seconds = timer.Seconds();
    return result;
  }
  // FLANN's Matrix takes a non-const pointer but the index does not write the data.
  flann::Matrix<float> data(const_cast<float*>(xyz.data()), n, 3);
  const std::vector<std::int32_t> order = MortonOrder(xyz);
  std::size_t retries = 0;
  auto run = [&](const auto& index, const flann::SearchParams& params) {
    const auto nn = static_cast<std::int64_t>(n);
#pragma omp parallel reduction(+ : retries)
    {
      std::vector<Entry> out;
#pragma omp for schedule(dynamic, 1024)
      for (std::int64_t t = 0; t < nn; ++t) {
        const std::int32_t i = order[t];
        Query(index, &xyz[3 * std::size_t(i)], i, k, n, params, out, retries);
        for (std::size_t c = 0; c < out.size(); ++c) {
          result.neighbors[std::size_t(i) * k + c] = out[c].i;
          result.sq_dist[std::size_t(i) * k + c] = out[c].d;
        }
      }
    }
  };
  if (options.checks <= 0) {
    flann::KDTreeSingleIndex<flann::L2_Simple<float>> index(data, flann::KDTreeSingleIndexParams(10));
    index.buildIndex();
    flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED, 0.0f, false);
    run(index, params);
  } else {
    flann::seed_random(12345);  // randomized trees: fixed seed, reproducible
    flann::KDTreeIndex<flann::L2_Simple<float>> index(data, flann::KDTreeIndexParams(4));
    index.buildIndex();
    flann::SearchParams params(options.checks, 0.0f, false);
    run(index, params);
  }
  result.tie_retries = retries;
  result.seconds = timer.Seconds();
  return result;
}


namespace {

// FLANN's exact kd-tree over n points (the data must outlive it), built on construction.
struct ExactIndex : flann::KDTreeSingleIndex<flann::L2_Simple<float>> {
  ExactIndex(float* data, std::size_t n)
      : flann::KDTreeSingleIndex<flann::L2_Simple<float>>(flann::Matrix<float>(data, n, 3),
                                                          flann::KDTreeSingleIndexParams(10)) {
    buildIndex();
  }
};
flann::SearchParams ExactSearch() { return flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED, 0.0f, false); }

// The k smallest (distance, index) entries of a row and a sorted candidate list.
void MergeInto(std::int32_t* nb, float* sd, int k, std::vector<Entry>& extra) {
  for (int c = 0; c < k; ++c)
    if (nb[c] >= 0) extra.push_back({sd[c], nb[c]});
  std::sort(extra.begin(), extra.end(), [](const Entry& a, const Entry& b) { return a.d < b.d || (a.d == b.d && a.i < b.i); });
  for (int c = 0; c < k; ++c) {
    nb[c] = c < int(extra.size()) ? extra[std::size_t(c)].i : -1;
    sd[c] = c < int(extra.size()) ? extra[std::size_t(c)].d : 0.0f;
  }
}

// Squared distance from p to the box [lo, hi] (a lower bound of its distance to any point inside).
double BoxDistance(const float* p, const float* lo, const float* hi) {
  double s = 0;
  for (int a = 0; a < 3; ++a) {
    const double g = p[a] < lo[a] ? double(lo[a]) - p[a] : (p[a] > hi[a] ? double(p[a]) - hi[a] : 0.0);
    s += g * g;
  }
  return s;
}

// The old points' lists: a point whose k-th neighbour is farther than some added point takes it in.
void AddedIntoOldLists(std::span<const float> xyz, std::span<const std::int32_t> new_of_old,
                       std::span<const std::int32_t> added, KnnResult& r, std::size_t& retries) {
  const int k = r.k;
  const std::size_t m = added.size();
  std::vector<float> axyz(3 * m);
  float lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = std::numeric_limits<float>::infinity(), hi[a] = -lo[a];
  for (std::size_t t = 0; t < m; ++t)
    for (int a = 0; a < 3; ++a) {
      axyz[3 * t + a] = xyz[3 * std::size_t(added[t]) + a];
      lo[a] = std::min(lo[a], axyz[3 * t + a]), hi[a] = std::max(hi[a], axyz[3 * t + a]);
    }
  const ExactIndex index(axyz.data(), m);
  const flann::SearchParams params = ExactSearch();
  const auto n_old = static_cast<std::int64_t>(new_of_old.size());
#pragma omp parallel reduction(+ : retries)
  {
    std::vector<Entry> out;
#pragma omp for schedule(dynamic, 4096)
    for (std::int64_t u = 0; u < n_old; ++u) {
      const std::size_t row = std::size_t(new_of_old[std::size_t(u)]);
      const float* q = &xyz[3 * row];
      std::int32_t* nb = &r.neighbors[row * k];
      float* sd = &r.sq_dist[row * k];
      // Rounding margin: FLANN's float distances against the box's double bound.
      if (nb[k - 1] >= 0 && BoxDistance(q, lo, hi) > double(sd[k - 1]) * (1.0 + 1e-5) + 1e-30) continue;
      Query(index, q, -1, k, m, params, out, retries);
      for (Entry& e : out) e.i = added[std::size_t(e.i)];
      MergeInto(nb, sd, k, out);
    }
  }
}

}  // namespace

KnnResult KnnWithAddedPoints(std::span<const float> xyz, const KnnResult& before,
                             std::span<const std::int32_t> new_of_old, std::span<const std::int32_t> added,
                             const KnnOptions& options) {
  options.Check();
  const std::size_t n = xyz.size() / 3;
  const int k = std::max(0, std::min<int>(options.k, static_cast<int>(n) - 1));
  if (k != before.k || k == 0 || added.empty() || options.checks > 0 ||
      before.neighbors.size() != new_of_old.size() * std::size_t(k))
    return KnnAmongPoints(xyz, options);
  Timer timer;
  KnnResult r;
  r.k = k;
  r.neighbors.assign(n * k, -1);
  r.sq_dist.assign(n * k, 0.0f);
  const auto n_old = static_cast<std::int64_t>(new_of_old.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t u = 0; u < n_old; ++u)
    for (int c = 0; c < k; ++c) {
      const std::int32_t v = before.neighbors[std::size_t(u) * k + c];
      r.neighbors[std::size_t(new_of_old[std::size_t(u)]) * k + c] = v >= 0 ? new_of_old[std::size_t(v)] : -1;
      r.sq_dist[std::size_t(new_of_old[std::size_t(u)]) * k + c] = before.sq_dist[std::size_t(u) * k + c];
    }
  std::size_t retries = 0;
  AddedIntoOldLists(xyz, new_of_old, added, r, retries);
  const ExactIndex index(const_cast<float*>(xyz.data()), n);
  const flann::SearchParams params = ExactSearch();
  // The added points' own lists (few: a list buffer per query costs nothing here).
  const auto m = static_cast<std::int64_t>(added.size());
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : retries)
  for (std::int64_t t = 0; t < m; ++t) {
    std::vector<Entry> out;
    const std::int32_t i = added[std::size_t(t)];
    Query(index, &xyz[3 * std::size_t(i)], i, k, n, params, out, retries);
    for (std::size_t c = 0; c < out.size(); ++c) {
      r.neighbors[std::size_t(i) * k + c] = out[c].i;
      r.sq_dist[std::size_t(i) * k + c] = out[c].d;
    }
  }
  r.tie_retries = before.tie_retries + retries;
  r.coincident = before.coincident;
  r.seconds = timer.Seconds();
  return r;
}

}  // namespace al
