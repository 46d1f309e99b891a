// .splat reader: the real chair file and hand-encoded records (RASTERIZER.md §10.4).
#include <cmath>
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/io/ply.hpp"
#include "test_data.hpp"

namespace al {
namespace {

constexpr float kC0 = 0.28209479177387814f;

std::string Record(const float pos[3], const float scale[3], const unsigned char rgba[4], const unsigned char rot[4]) {
  std::string r(32, '\0');
  std::memcpy(r.data(), pos, 12);
  std::memcpy(r.data() + 12, scale, 12);
  std::memcpy(r.data() + 24, rgba, 4);
  std::memcpy(r.data() + 28, rot, 4);
  return r;
}

TEST(SplatReader, DecodesHandEncodedRecords) {
  const float pos[3] = {1.5f, -2.0f, 0.25f}, scale[3] = {0.5f, 1.0f, 2.0f};
  const unsigned char rgba[4] = {255, 128, 0, 204}, rot[4] = {128 + 90, 128, 128 - 90, 128};
  const unsigned char rgba0[4] = {0, 0, 0, 0}, rot0[4] = {128, 128, 128, 128};
  const std::string bytes = Record(pos, scale, rgba, rot) + Record(pos, scale, rgba0, rot0);
  const Scene s = ReadSplatFromMemory(bytes.data(), bytes.size(), "m.splat");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s.source_format, "splat");
  EXPECT_EQ(s.sh_degree, 0);
  EXPECT_EQ(s.means.row(0), Eigen::RowVector3f(1.5f, -2.0f, 0.25f));
  EXPECT_NEAR(s.log_scales(0, 0), std::log(0.5f), 1e-6f);
  EXPECT_NEAR(s.log_scales(0, 2), std::log(2.0f), 1e-6f);
  EXPECT_NEAR(0.5f + kC0 * s.sh(0, 0), 1.0f, 1e-6f);
  EXPECT_NEAR(0.5f + kC0 * s.sh(0, 2), 0.0f, 1e-6f);
  EXPECT_NEAR(1.0f / (1.0f + std::exp(-s.opacity_logits(0))), 204.0f / 255.0f, 1e-5f);
  EXPECT_NEAR(s.rotations(0, 0), std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(s.rotations(0, 2), -std::sqrt(0.5f), 1e-6f);
  EXPECT_TRUE(std::isfinite(s.opacity_logits(1)));  // alpha 0 clamped
  EXPECT_EQ(s.rotations.row(1), Eigen::RowVector4f(1, 0, 0, 0));
}

TEST(SplatReader, RejectsBadSizes) {
  const std::string bytes(33, '\0');
  for (std::size_t size : {std::size_t(0), std::size_t(33), std::size_t(31)}) {
    try {
      ReadSplatFromMemory(bytes.data(), size, "bad.splat");
      FAIL() << size;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("bad.splat: ", 0), 0u);
    }
  }
}

TEST(SplatReader, Chair111k) {
  AL_REQUIRE_SHARED_DATA(data);
  const Scene s = ReadScene((data / "real_ply" / "chair_111k.splat").string());
  ASSERT_EQ(s.size(), 111650u);
  EXPECT_TRUE(s.log_scales.allFinite());  // all scales finite and > 0
  EXPECT_GE(s.log_scales.minCoeff(), std::log(7.5e-9f));
  EXPECT_LE(s.log_scales.maxCoeff(), std::log(0.48f));
  double mean_abs_w = 0;
  for (Eigen::Index i = 0; i < s.rotations.rows(); ++i) {
    ASSERT_NEAR(s.rotations.row(i).norm(), 1.0f, 1e-5f) << i;
    mean_abs_w += std::abs(s.rotations(i, 0));
  }
  EXPECT_GT(mean_abs_w / double(s.size()), 0.8);  // README: w first, mean |w| = 0.84
  EXPECT_LE(s.means.cwiseAbs().maxCoeff(), 1.48f);
  EXPECT_EQ(CountNonFinite(s).gaussians_with_any, 0u);
}

}  // namespace
}  // namespace al
