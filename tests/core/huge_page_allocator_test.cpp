// HugePageAllocator: large requests are 2 MiB-aligned (so the kernel can back them with huge
// pages), small ones are ordinary; vectors using it behave like std::vector (contents survive
// growth, value-initialisation on resize).
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "al/core/huge_page_allocator.hpp"

namespace {

template <class T>
using HugeVector = std::vector<T, al::HugePageAllocator<T>>;

TEST(HugePageAllocator, LargeBuffersAreHugePageAligned) {
  HugeVector<double> big(1 << 20);  // 8 MiB
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(big.data()) % al::HugePageAllocator<double>::kHugePage, 0u);
  for (double x : big) ASSERT_EQ(x, 0.0);
  HugeVector<double> small(10);
  EXPECT_EQ(small.size(), 10u);
}

TEST(HugePageAllocator, ContentsSurviveGrowthAcrossTheThreshold) {
  HugeVector<std::int32_t> v;
  for (std::int32_t i = 0; i < 3'000'000; ++i) v.push_back(i);  // crosses 2 MiB several times
  for (std::int32_t i = 0; i < 3'000'000; i += 9973) ASSERT_EQ(v[i], i);
  v.resize(10);
  v.shrink_to_fit();
  EXPECT_EQ(v.back(), 9);
  v.assign(1'000'000, 7);
  EXPECT_EQ(v[999'999], 7);
}

// Without the advice: the same alignment and contents; the flag follows rebinding and copies, and
// a vector without it can take over one with it (both free alike).
TEST(HugePageAllocator, WithoutAdviceKeepsAlignmentAndMixesWithAdvised) {
  const al::HugePageAllocator<double> plain(false);
  EXPECT_FALSE(plain.advise);
  EXPECT_FALSE(al::HugePageAllocator<int>(plain).advise);
  EXPECT_TRUE(al::HugePageAllocator<double>().advise);
  HugeVector<double> big(1 << 20, 1.5, plain);
  EXPECT_FALSE(big.get_allocator().advise);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(big.data()) % al::HugePageAllocator<double>::kHugePage, 0u);
  for (int i = 0; i < 1000; ++i) big.push_back(double(i));  // regrows through the same allocator
  EXPECT_FALSE(big.get_allocator().advise);
  EXPECT_EQ(big.back(), 999.0);
  HugeVector<double> advised(1 << 20, 2.5);
  advised = std::move(big);
  EXPECT_EQ(advised[0], 1.5);
  EXPECT_EQ(advised.size(), std::size_t(1 << 20) + 1000);
}

}  // namespace
