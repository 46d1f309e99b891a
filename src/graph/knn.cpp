// FLANN kNN with deterministic tie-breaking (see knn.hpp).
#include "al/graph/knn.hpp"

#include "al/core/option_table.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <parallel/algorithm>

#include <flann/flann.hpp>

#include "al/core/first_touch.hpp"
#include "al/core/timer.hpp"
#include "point_tree.hpp"

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

// (63-bit Morton code, point index), sorted: the points along a Z-order curve over their box.
using MortonCodes = std::vector<std::pair<std::uint64_t, std::int32_t>>;

MortonCodes SortedMortonCodes(std::span<const float> xyz) {
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
  MortonCodes code(n);
  const auto nn = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < nn; ++i) {
    std::uint64_t c = 0;
    for (int a = 0; a < 3; ++a) {
      const double ext = double(hi[a]) - lo[a];
      const double t = ext > 0 ? (double(xyz[3 * std::size_t(i) + a]) - lo[a]) / ext : 0.0;
      c |= Spread3(static_cast<std::uint64_t>(t * 2097151.0)) << a;
    }
    code[std::size_t(i)] = {c, static_cast<std::int32_t>(i)};
  }
  // Keys are unique (the index breaks ties), so the parallel sort's order is the sequential one.
  __gnu_parallel::sort(code.begin(), code.end());
  return code;
}

// A list entry: (squared distance, index), ordered by NeighborBefore (point_tree.hpp).
using Entry = TreeNeighbor;

// Neighbours asked for beyond the k + 1 a query needs: room for a tie at the k-th before a second
// search is needed. Exact search gives the same lists for any value; a larger one only makes
// every search keep (and insert into) a longer list.
constexpr std::size_t kTieSlack = 1;

// Squared distance from p to the box [lo, hi] (a lower bound of its distance to any point inside).
double BoxDistance(const float* p, const float* lo, const float* hi) {
  double s = 0;
  for (int a = 0; a < 3; ++a) {
    const double g = p[a] < lo[a] ? double(lo[a]) - p[a] : (p[a] > hi[a] ? double(p[a]) - hi[a] : 0.0);
    s += g * g;
  }
  return s;
}

// One thread's buffers for its queries: a result set and two lists per query cost as much in
// allocations as a 3-D search.
struct QueryScratch {
  std::unique_ptr<flann::KNNSimpleResultSet<float>> rs;
  std::size_t capacity = 0;
  std::vector<std::size_t> idx;
  std::vector<float> dist;
  std::vector<Entry> out;
  std::vector<TreeNeighbor> found;
};

// The m nearest points of q in the index (fewer when it holds fewer) into s.idx / s.dist,
// nearest first; returns how many.
template <class Index>
std::size_t Search(const Index& index, const float* q, std::size_t m, const flann::SearchParams& params,
                   QueryScratch& s) {
  if (!s.rs || s.capacity != m) {
    s.rs = std::make_unique<flann::KNNSimpleResultSet<float>>(m);
    s.capacity = m;
  } else {
    s.rs->clear();
  }
  index.findNeighbors(*s.rs, q, params);
  const std::size_t got = s.rs->size();
  s.idx.resize(got);
  s.dist.resize(got);
  if (got > 0) s.rs->copy(s.idx.data(), s.dist.data(), got);
  return got;
}

// The same from the exact tree, whose lists already hold ties in index order.
std::size_t Search(const PointTree& tree, const float* q, std::size_t m, const flann::SearchParams&, QueryScratch& s) {
  tree.Nearest(q, m, -1, s.found);
  const std::size_t got = s.found.size();
  s.idx.resize(got);
  s.dist.resize(got);
  for (std::size_t t = 0; t < got; ++t) s.idx[t] = std::size_t(s.found[t].i), s.dist[t] = s.found[t].d;
  return got;
}

// One query: s.out = sorted (dist, index) list of the k nearest points other than `self`.
template <class Index>
void Query(const Index& index, const float* q, std::int32_t self, int k, std::size_t n,
           const flann::SearchParams& params, QueryScratch& s, std::size_t& retries) {
  std::size_t m = std::min<std::size_t>(n, static_cast<std::size_t>(k) + 1 + kTieSlack);
  std::vector<Entry>& out = s.out;
  for (;;) {
    const std::size_t got = Search(index, q, m, params, s);
    out.clear();
    for (std::size_t t = 0; t < got; ++t)
      if (static_cast<std::int32_t>(s.idx[t]) != self) out.push_back({s.dist[t], static_cast<std::int32_t>(s.idx[t])});
    std::sort(out.begin(), out.end(), NeighborBefore);
    // Complete when every point was returned, or the k-th kept neighbour is strictly closer
    // than the farthest returned point (so no unseen point can tie with it).
    const bool all = got >= n || got < m;
    if (all || (out.size() >= static_cast<std::size_t>(k) && out[k - 1].d < s.dist[got - 1])) break;
    m = std::min(n, 2 * m);
    ++retries;
  }
  if (out.size() > static_cast<std::size_t>(k)) out.resize(k);
}

// Exactly coincident points (same coordinates) as groups: points[begin[g]..begin[g+1]) are the
// members of group g in ascending index; groups are numbered by their first member rep[g].
// Empty when all are distinct.
struct Groups {
  std::vector<std::int32_t> group_of, members, begin, rep;
};

using CoordKey = std::array<std::uint32_t, 3>;  // a point's coordinate bits: equal keys = coincident
CoordKey KeyOf(std::span<const float> xyz, std::int32_t i) {
  CoordKey k;
  std::memcpy(k.data(), &xyz[3 * std::size_t(i)], sizeof k);
  return k;
}

// Per point, the smallest index at exactly its position. Coincident points share a Morton code,
// so only runs of equal codes in the sorted code list need their keys compared.
std::vector<std::int32_t> FirstAtSamePosition(std::span<const float> xyz, const MortonCodes& sorted) {
  const std::size_t n = sorted.size();
  std::vector<std::int32_t> first(n);
  std::vector<std::int32_t> run;
  for (std::size_t t = 0; t < n;) {
    std::size_t e = t + 1;
    while (e < n && sorted[e].first == sorted[t].first) ++e;
    if (e == t + 1) {
      first[std::size_t(sorted[t].second)] = sorted[t].second;
    } else {
      run.clear();
      for (std::size_t r = t; r < e; ++r) run.push_back(sorted[r].second);
      std::sort(run.begin(), run.end(), [&](std::int32_t a, std::int32_t b) {
        const CoordKey ka = KeyOf(xyz, a), kb = KeyOf(xyz, b);
        return ka != kb ? ka < kb : a < b;
      });
      for (std::size_t r = 0; r < run.size(); ++r)
        first[std::size_t(run[r])] = r > 0 && KeyOf(xyz, run[r]) == KeyOf(xyz, run[r - 1]) ? first[std::size_t(run[r - 1])] : run[r];
    }
    t = e;
  }
  return first;
}

Groups GroupCoincident(std::span<const float> xyz, const MortonCodes& sorted) {
  const std::size_t n = sorted.size();
  const std::vector<std::int32_t> first = FirstAtSamePosition(xyz, sorted);
  std::size_t m = 0;
  for (std::size_t i = 0; i < n; ++i) m += first[i] == std::int32_t(i);
  if (m == n) return {};
  Groups g;
  g.group_of.resize(n);
  g.begin.assign(m + 1, 0);
  g.rep.reserve(m);
  for (std::size_t i = 0; i < n; ++i) {  // ascending index: a group is numbered at its first member
    if (first[i] == std::int32_t(i)) g.rep.push_back(std::int32_t(i));
    g.group_of[i] = first[i] == std::int32_t(i) ? std::int32_t(g.rep.size() - 1) : g.group_of[std::size_t(first[i])];
    ++g.begin[std::size_t(g.group_of[i]) + 1];
  }
  for (std::size_t u = 0; u < m; ++u) g.begin[u + 1] += g.begin[u];
  g.members.resize(n);
  std::vector<std::int32_t> at(g.begin.begin(), g.begin.end() - 1);
  for (std::size_t i = 0; i < n; ++i) g.members[std::size_t(at[std::size_t(g.group_of[i])]++)] = std::int32_t(i);
  return g;
}

// The k + 1 smallest (distance, index) pairs over all points, for a query at unique point u:
// its own group at distance 0, then the groups of its nearest unique points. A group contributes
// at most `want` members (its smallest indices), so a group of 100k coincident points costs O(k)
// instead of 100k per query (the tie retry would otherwise grow to the whole group).
template <class Index>
void QueryGroup(const Index& index, const float* q, std::int32_t u, std::size_t want, const Groups& g,
                const flann::SearchParams& params, QueryScratch& s, std::size_t& retries) {
  const std::size_t m = g.rep.size();
  std::size_t ask = std::min<std::size_t>(m, want + 1 + kTieSlack);
  std::vector<Entry>& out = s.out;
  for (;;) {
    const std::size_t got = Search(index, q, ask, params, s);
    out.clear();
    for (std::int32_t t = g.begin[u]; t < g.begin[u + 1] && out.size() < want; ++t) out.push_back({0.0f, g.members[t]});
    for (std::size_t t = 0; t < got; ++t) {
      const auto v = static_cast<std::int32_t>(s.idx[t]);
      if (v == u) continue;
      const std::int32_t end = std::min<std::int32_t>(g.begin[v + 1], g.begin[v] + std::int32_t(want));
      for (std::int32_t r = g.begin[v]; r < end; ++r) out.push_back({s.dist[t], g.members[r]});
    }
    std::sort(out.begin(), out.end(), NeighborBefore);
    const bool all = got >= m || got < ask;
    if (all || (out.size() >= want && out[want - 1].d < s.dist[got - 1])) break;
    ask = std::min(m, 2 * ask);
    ++retries;
  }
  if (out.size() > want) out.resize(want);
}

// KnnAmongPoints when some points coincide: one query per unique point, on a tree of unique points.
template <class Index>
void KnnGrouped(const Index& index, std::span<const float> uxyz, const Groups& g, const std::vector<std::int32_t>& order,
                int k, const flann::SearchParams& params, KnnResult& result, std::size_t& retries) {
  const auto m = static_cast<std::int64_t>(g.rep.size());
#pragma omp parallel reduction(+ : retries)
  {
    QueryScratch scratch;
#pragma omp for schedule(dynamic, 256)
    for (std::int64_t t = 0; t < m; ++t) {
      const std::int32_t u = order[t];
      QueryGroup(index, &uxyz[3 * std::size_t(u)], u, std::size_t(k) + 1, g, params, scratch, retries);
      for (std::int32_t s = g.begin[u]; s < g.begin[u + 1]; ++s) {
        const std::int32_t i = g.members[s];
        std::size_t c = 0;
        for (const Entry& e : scratch.out) {
          if (e.i == i || c == std::size_t(k)) continue;
          result.neighbors[std::size_t(i) * k + c] = e.i;
          result.sq_dist[std::size_t(i) * k + c] = e.d;
          ++c;
        }
      }
    }
  }
}

// Exact search looks for piles of coincident points in the tree's leaves first (PointTree::
// LargestPileInALeaf): with none above this many, the points are searched as they are — a query
// in a pile of p scans the p - 1 others at distance 0, the lists are the same — and neither the
// Morton sort nor the grouping runs (3M room scene, 58 points in piles of 2: kNN 0.47 -> 0.39 s
// without one query per position, 0.40 -> 0.38 s without the sort). A larger pile (100k copies of a
// point would make every query in it scan the pile) gets one query per position.
constexpr std::size_t kSmallPile = 8;

// Points at exactly the position of an earlier point, from exact lists: such a point's list
// starts with the zero distances, smallest indices first.
std::size_t CountCoincident(std::span<const float> xyz, const KnnResult& r) {
  const auto n = static_cast<std::int64_t>(xyz.size() / 3);
  const int k = r.k;
  std::size_t count = 0;
#pragma omp parallel for schedule(static) reduction(+ : count)
  for (std::int64_t i = 0; i < n; ++i)
    for (int c = 0; c < k && r.sq_dist[std::size_t(i) * k + c] == 0.0f; ++c) {
      const std::int32_t j = r.neighbors[std::size_t(i) * k + c];
      if (j < i && KeyOf(xyz, j) == KeyOf(xyz, std::int32_t(i))) {
        ++count;
        break;
      }
    }
  return count;
}

// KnnAmongPoints when some points coincide: queries and trees over the unique positions.
void KnnAmongUnique(std::span<const float> xyz, const MortonCodes& codes, const Groups& groups, int checks,
                    KnnResult& result) {
  std::vector<float> uxyz(3 * groups.rep.size());
  for (std::size_t u = 0; u < groups.rep.size(); ++u) std::copy_n(&xyz[3 * std::size_t(groups.rep[u])], 3, &uxyz[3 * u]);
  std::size_t retries = 0;
  if (checks <= 0) {
    const PointTree tree(uxyz);
    KnnGrouped(tree, uxyz, groups, tree.order(), result.k, flann::SearchParams(), result, retries);
  } else {
    std::vector<std::int32_t> order;  // the unique points in Morton order (their first members')
    order.reserve(groups.rep.size());
    for (const auto& [code, i] : codes)
      if (groups.rep[std::size_t(groups.group_of[std::size_t(i)])] == i) order.push_back(groups.group_of[std::size_t(i)]);
    flann::seed_random(12345);
    flann::Matrix<float> udata(uxyz.data(), groups.rep.size(), 3);
    flann::KDTreeIndex<flann::L2_Simple<float>> index(udata, flann::KDTreeIndexParams(4));
    index.buildIndex();
    KnnGrouped(index, uxyz, groups, order, result.k, flann::SearchParams(checks, 0.0f, false), result, retries);
  }
  result.tie_retries = retries;
}

// The lists of the points `queries` (indices into xyz, the tree's points) into result's rows.
void ListsFromTree(const PointTree& tree, std::span<const float> xyz, std::span<const std::int32_t> queries,
                   KnnResult& result) {
  const int k = result.k;
  const auto n = static_cast<std::int64_t>(queries.size());
#pragma omp parallel
  {
    std::vector<TreeNeighbor> found;
#pragma omp for schedule(dynamic, 512)
    for (std::int64_t t = 0; t < n; ++t) {
      const std::int32_t i = queries[std::size_t(t)];
      tree.Nearest(&xyz[3 * std::size_t(i)], std::size_t(k), i, found);
      for (std::size_t c = 0; c < found.size(); ++c) {
        result.neighbors[std::size_t(i) * k + c] = found[c].i;
        result.sq_dist[std::size_t(i) * k + c] = found[c].d;
      }
    }
  }
}

// Distinct points (or small piles), exact: one descent per point, queries in the tree's leaf
// order. (Seeding a query with the previous one and its list, to prune from the first leaf on,
// scanned 2 % fewer leaves and took 20 % longer.)
void KnnExact(std::span<const float> xyz, const PointTree& tree, KnnResult& result) {
  ListsFromTree(tree, xyz, tree.order(), result);
}

// Distinct points, FLANN's randomized trees (fixed seed: reproducible), queries in Morton order.
void KnnApproximate(std::span<const float> xyz, const MortonCodes& codes, int checks, KnnResult& result) {
  const std::size_t n = xyz.size() / 3;
  const int k = result.k;
  flann::seed_random(12345);
  // FLANN's Matrix takes a non-const pointer but the index does not write the data.
  flann::Matrix<float> data(const_cast<float*>(xyz.data()), n, 3);
  flann::KDTreeIndex<flann::L2_Simple<float>> index(data, flann::KDTreeIndexParams(4));
  index.buildIndex();
  const flann::SearchParams params(checks, 0.0f, false);
  std::size_t retries = 0;
  const auto nn = static_cast<std::int64_t>(n);
#pragma omp parallel reduction(+ : retries)
  {
    QueryScratch s;
#pragma omp for schedule(dynamic, 1024)
    for (std::int64_t t = 0; t < nn; ++t) {
      const std::int32_t i = codes[std::size_t(t)].second;
      Query(index, &xyz[3 * std::size_t(i)], i, k, n, params, s, retries);
      for (std::size_t c = 0; c < s.out.size(); ++c) {
        result.neighbors[std::size_t(i) * k + c] = s.out[c].i;
        result.sq_dist[std::size_t(i) * k + c] = s.out[c].d;
      }
    }
  }
  result.tie_retries = retries;
}

}  // namespace

std::vector<std::int32_t> MortonOrder(std::span<const float> xyz) {
  const MortonCodes code = SortedMortonCodes(xyz);
  std::vector<std::int32_t> order(code.size());
  for (std::size_t i = 0; i < code.size(); ++i) order[i] = code[i].second;
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
  ReserveFirstTouched(result.neighbors, n * k);
  ReserveFirstTouched(result.sq_dist, n * k);
  result.neighbors.assign(n * k, -1);
  result.sq_dist.assign(n * k, 0.0f);
  if (k <= 0) {
    result.seconds = timer.Seconds();
    return result;
  }
  if (options.checks <= 0) {
    const PointTree tree(xyz);
    if (tree.LargestPileInALeaf() <= kSmallPile) {
      KnnExact(xyz, tree, result);
      result.coincident = CountCoincident(xyz, result);
      result.seconds = timer.Seconds();
      return result;
    }
  }
  // Exact search gets here only with a pile in a leaf, so with coincident points to group.
  const MortonCodes codes = SortedMortonCodes(xyz);
  const Groups groups = GroupCoincident(xyz, codes);
  if (groups.rep.empty()) {
    KnnApproximate(xyz, codes, options.checks, result);
  } else {
    result.coincident = n - groups.rep.size();
    KnnAmongUnique(xyz, codes, groups, options.checks, result);
  }
  result.seconds = timer.Seconds();
  return result;
}

namespace {

// The k smallest (distance, index) entries of a row and a sorted candidate list.
void MergeInto(std::int32_t* nb, float* sd, int k, std::vector<TreeNeighbor>& extra) {
  for (int c = 0; c < k; ++c)
    if (nb[c] >= 0) extra.push_back({sd[c], nb[c]});
  std::sort(extra.begin(), extra.end(), NeighborBefore);
  for (int c = 0; c < k; ++c) {
    nb[c] = c < int(extra.size()) ? extra[std::size_t(c)].i : -1;
    sd[c] = c < int(extra.size()) ? extra[std::size_t(c)].d : 0.0f;
  }
}

// The old points' lists: a point whose k-th neighbour is farther than some added point takes it in.
void AddedIntoOldLists(std::span<const float> xyz, std::span<const std::int32_t> new_of_old,
                       std::span<const std::int32_t> added, KnnResult& r) {
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
  const PointTree tree(axyz);
  const auto n_old = static_cast<std::int64_t>(new_of_old.size());
#pragma omp parallel
  {
    std::vector<TreeNeighbor> found;
#pragma omp for schedule(dynamic, 4096)
    for (std::int64_t u = 0; u < n_old; ++u) {
      const std::size_t row = std::size_t(new_of_old[std::size_t(u)]);
      const float* q = &xyz[3 * row];
      std::int32_t* nb = &r.neighbors[row * k];
      float* sd = &r.sq_dist[row * k];
      // Rounding margin: float distances against the box's double bound.
      if (nb[k - 1] >= 0 && BoxDistance(q, lo, hi) > double(sd[k - 1]) * (1.0 + 1e-5) + 1e-30) continue;
      tree.Nearest(q, std::size_t(k), -1, found);
      for (TreeNeighbor& e : found) e.i = added[std::size_t(e.i)];
      MergeInto(nb, sd, k, found);
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
  AddedIntoOldLists(xyz, new_of_old, added, r);
  ListsFromTree(PointTree(xyz), xyz, added, r);  // the added points' own lists
  r.tie_retries = before.tie_retries;
  r.coincident = before.coincident;
  r.seconds = timer.Seconds();
  return r;
}

}  // namespace al
