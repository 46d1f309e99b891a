// Candidate growth equals the brute-force O(|R|·N) sphere test, with huge Gaussians, duplicates,
// non-finite exclusions and several hops.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "al/graph/candidates.hpp"
#include "graph_test_util.hpp"

namespace {

std::vector<std::uint8_t> BruteForce(const std::vector<float>& xyz, const std::vector<double>& r,
                                     const std::vector<std::uint8_t>& active,
                                     const std::vector<std::uint8_t>& seeds, int hops) {
  const std::size_t N = r.size();
  std::vector<std::uint8_t> in(N, 0), frontier(N, 0);
  for (std::size_t i = 0; i < N; ++i) in[i] = frontier[i] = seeds[i] && active[i];
  for (int h = 0; h < hops; ++h) {
    std::vector<std::uint8_t> next(N, 0);
    for (std::size_t j = 0; j < N; ++j) {
      if (in[j] || !active[j]) continue;
      for (std::size_t i = 0; i < N && !next[j]; ++i)
        if (frontier[i] && al::SpheresIntersect(&xyz[3 * i], r[i], &xyz[3 * j], r[j])) next[j] = 1;
    }
    for (std::size_t j = 0; j < N; ++j) in[j] |= next[j];
    frontier = next;
  }
  return in;
}

TEST(Candidates, EqualBruteForceWithHugeSpheresDuplicatesAndHops) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    auto g = al::test::MakeGraphScene(1500 + 300 * seed, seed, 4, /*huge=*/seed % 4, /*dups=*/40);
    const std::size_t N = g.scene.size();
    std::vector<float> xyz(3 * N);
    std::vector<double> r(N);
    std::vector<std::uint8_t> active(N, 1), seeds(N);
    for (std::size_t i = 0; i < N; ++i) {
      for (int a = 0; a < 3; ++a) xyz[3 * i + a] = g.scene.means(i, a);
      r[i] = std::exp(double(g.scene.log_scales.row(i).maxCoeff()));
      seeds[i] = g.removed[i];
      if (i % 97 == 5) active[i] = 0;
    }
    for (int hops : {0, 1, 2, 3}) {
      al::CandidateStats st;
      const auto fast = al::GrowCandidates(xyz, r, active, seeds, hops, &st);
      const auto brute = BruteForce(xyz, r, active, seeds, hops);
      ASSERT_EQ(fast, brute) << "seed " << seed << " hops " << hops;
      std::size_t added = 0;
      for (auto a : st.added_per_hop) added += a;
      std::size_t total = 0;
      for (auto v : fast) total += v;
      EXPECT_EQ(total, st.seeds + added);
    }
  }
}

TEST(Candidates, EmptySeedsGiveEmptySet) {
  std::vector<float> xyz{0, 0, 0, 1, 1, 1};
  std::vector<double> r{1, 1};
  std::vector<std::uint8_t> active{1, 1}, seeds{0, 0};
  const auto in = al::GrowCandidates(xyz, r, active, seeds, 2);
  EXPECT_EQ(in, (std::vector<std::uint8_t>{0, 0}));
}

TEST(Candidates, TouchingSpheresAreNotCandidates) {
  // Strict inequality: centres 2 apart with radii 1 + 1 touch but do not intersect.
  std::vector<float> xyz{0, 0, 0, 2, 0, 0, 1.5f, 0, 0};
  std::vector<double> r{1, 1, 0.6};
  std::vector<std::uint8_t> active{1, 1, 1}, seeds{1, 0, 0};
  const auto in = al::GrowCandidates(xyz, r, active, seeds, 1);
  EXPECT_EQ(in, (std::vector<std::uint8_t>{1, 0, 1}));
}

}  // namespace
