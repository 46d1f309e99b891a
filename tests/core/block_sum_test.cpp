// BlockSum2: the same double for any thread count, equal to the plain sum up to rounding, and the
// two terms kept apart until the end.
#include "al/core/block_sum.hpp"

#include <omp.h>

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace al {
namespace {

TEST(BlockSum2, SameDoubleForEveryThreadCountAndCloseToThePlainSum) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int before = omp_get_max_threads();
  for (const std::int64_t n : {std::int64_t{0}, std::int64_t{1}, std::int64_t{16383}, std::int64_t{16385}, std::int64_t{100000}}) {
    std::vector<double> a(n), b(n);
    for (std::int64_t i = 0; i < n; ++i) a[i] = u(rng) * 1e6, b[i] = u(rng) * 1e-3;
    auto term = [&](std::int64_t i, double& x, double& y) { x += a[i], y += b[i]; };
    omp_set_num_threads(1);
    const double one = BlockSum2(n, term);
    double plain_a = 0.0, plain_b = 0.0;
    for (std::int64_t i = 0; i < n; ++i) plain_a += a[i], plain_b += b[i];
    EXPECT_NEAR(one, plain_a + plain_b, 1e-6) << n;
    for (const int threads : {2, 3, 8}) {
      omp_set_num_threads(threads);
      EXPECT_EQ(BlockSum2(n, term), one) << n << " with " << threads << " threads";
    }
  }
  omp_set_num_threads(before);
}

}  // namespace
}  // namespace al
