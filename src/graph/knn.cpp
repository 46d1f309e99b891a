// FLANN kNN with deterministic tie-breaking (see knn.hpp).
#include "al/graph/knn.hpp"

#include <algorithm>
#include <cmath>
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

KnnResult KnnAmongPoints(std::span<const float> xyz, const KnnOptions& options) {
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

}  // namespace al
