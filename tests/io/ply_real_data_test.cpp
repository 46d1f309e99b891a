// The real files in ../shared/data: values checked against bytes read independently at known offsets.
#include <cmath>
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/io/ply.hpp"
#include "test_data.hpp"

namespace al {
namespace {

constexpr std::size_t kHeader9k = 1529, kRecord = 248;

std::string ReadBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

float FloatAt(const std::string& bytes, std::size_t offset) {
  float v;
  std::memcpy(&v, bytes.data() + offset, 4);
  return v;
}

TEST(PlyRealData, Scene9kValuesMatchBytesAtKnownOffsets) {
  AL_REQUIRE_SHARED_DATA(data);
  const auto path = data / "real_ply" / "scene_9k.ply";
  const std::string bytes = ReadBytes(path);
  ASSERT_EQ(bytes.size(), kHeader9k + 9080 * kRecord);
  const Scene s = ReadPly(path.string());
  ASSERT_EQ(s.size(), 9080u);
  EXPECT_EQ(s.sh_degree, 3);
  EXPECT_EQ(s.sh.cols(), 48);
  EXPECT_EQ(s.ply->header.size(), kHeader9k);
  EXPECT_EQ(s.ply->record_bytes, kRecord);
  EXPECT_EQ(s.features.size(), 0);
  for (std::size_t i : {0u, 1u, 4539u, 9079u}) {
    const std::size_t r = kHeader9k + i * kRecord;
    const Eigen::Index e = static_cast<Eigen::Index>(i);
    EXPECT_EQ(s.means(e, 0), FloatAt(bytes, r + 0));
    EXPECT_EQ(s.means(e, 2), FloatAt(bytes, r + 2 * 4));
    EXPECT_EQ(s.sh(e, 1), FloatAt(bytes, r + 7 * 4));                // f_dc_1
    EXPECT_EQ(s.sh(e, 2 * 3 + 1), FloatAt(bytes, r + (9 + 16) * 4));  // f_rest_16 = G, k = 2
    EXPECT_EQ(s.sh(e, 15 * 3 + 2), FloatAt(bytes, r + (9 + 44) * 4));  // f_rest_44 = B, k = 15
    EXPECT_EQ(s.opacity_logits(e), FloatAt(bytes, r + 54 * 4));
    EXPECT_EQ(s.log_scales(e, 2), FloatAt(bytes, r + 57 * 4));
    EXPECT_EQ(s.rotations(e, 3), FloatAt(bytes, r + 61 * 4));
  }
  // README ranges.
  EXPECT_GE(s.means.col(0).minCoeff(), -411.0f);
  EXPECT_LE(s.means.col(2).maxCoeff(), 1005.0f);
  EXPECT_GE(s.opacity_logits.minCoeff(), -5.27f);
  EXPECT_LE(s.opacity_logits.maxCoeff(), 3.62f);
  EXPECT_EQ(CountNonFinite(s).gaussians_with_any, 0u);
}

TEST(PlyRealData, SubsetWriterCopiesScene9kRecordsByteForByte) {
  AL_REQUIRE_SHARED_DATA(data);
  const auto path = data / "real_ply" / "scene_9k.ply";
  const std::string bytes = ReadBytes(path);
  const Scene s = ReadPly(path.string());
  std::vector<bool> keep(s.size());
  std::size_t kept = 0;
  for (std::size_t i = 0; i < keep.size(); ++i) kept += (keep[i] = (i % 3 == 1 || i > 9000));
  const auto out = test::TempDir() / "subset.ply";
  WritePly(out.string(), s, keep);
  const std::string written = ReadBytes(out);
  std::string header = bytes.substr(0, kHeader9k);
  const std::string from = "element vertex 9080\n", to = "element vertex " + std::to_string(kept) + "\n";
  header.replace(header.find(from), from.size(), to);
  ASSERT_EQ(written.size(), header.size() + kept * kRecord);
  EXPECT_EQ(written.substr(0, header.size()), header);
  std::size_t j = 0;
  for (std::size_t i = 0; i < keep.size(); ++i) {
    if (!keep[i]) continue;
    ASSERT_EQ(std::memcmp(written.data() + header.size() + j * kRecord, bytes.data() + kHeader9k + i * kRecord, kRecord), 0)
        << "record " << i;
    ++j;
  }
  // Full rewrite is the identical file.
  WritePly(out.string(), s);
  EXPECT_EQ(ReadBytes(out), bytes);
}

TEST(PlyRealData, TruncatedScene9kThrowsNamingTheFile) {
  AL_REQUIRE_SHARED_DATA(data);
  const std::string bytes = ReadBytes(data / "real_ply" / "scene_9k.ply");
  const auto dir = test::TempDir();
  for (std::size_t cut : {std::size_t(10), std::size_t(kHeader9k - 5), std::size_t(kHeader9k + 1000), bytes.size() - 1}) {
    const auto path = (dir / ("cut_" + std::to_string(cut) + ".ply")).string();
    std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(cut));
    try {
      ReadPly(path);
      FAIL() << "no error for a copy cut at " << cut;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    }
  }
}

TEST(PlyRealData, Tiny16MatchesTheDocumentedValues) {
  AL_REQUIRE_SHARED_DATA(data);
  const Scene s = ReadPly((data / "parsers" / "tiny_16.ply").string());
  ASSERT_EQ(s.size(), 16u);
  EXPECT_EQ(s.ply->header.size(), 1527u);
  EXPECT_EQ(s.sh_degree, 3);
  const float c0 = 0.28209479177387814f;
  int red = 0, green = 0, blue = 0, white = 0;
  for (Eigen::Index i = 0; i < 16; ++i) {
    EXPECT_NEAR(s.opacity_logits(i), 100.0f, 1e-4f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.log_scales(i, c), -2.9957f, 1e-4f);
    EXPECT_EQ(s.rotations.row(i), Eigen::RowVector4f(1, 0, 0, 0));
    for (int k = 3; k < 48; ++k) EXPECT_EQ(s.sh(i, k), 0.0f);
    float rgb[3];
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(std::abs(s.sh(i, c)), 0.5f / c0, 1e-4f);
      rgb[c] = std::round(0.5f + c0 * s.sh(i, c));
    }
    const auto m = s.means.row(i);
    if (rgb[0] == 1 && rgb[1] == 1 && rgb[2] == 1) {
      ++white;
      EXPECT_EQ(m.norm(), 0.0f);
    } else if (rgb[0] == 1) {
      ++red;
      EXPECT_GE(m(0), 0.2f - 1e-6f);
      EXPECT_EQ(m(1), 0.0f);
    } else if (rgb[1] == 1) {
      ++green;
      EXPECT_GE(m(1), 0.2f - 1e-6f);
    } else if (rgb[2] == 1) {
      ++blue;
      EXPECT_GE(m(2), 0.2001f - 1e-6f);
      EXPECT_LE(m(2), 1.0001f + 1e-6f);
    }
  }
  EXPECT_EQ(red, 5);
  EXPECT_EQ(green, 5);
  EXPECT_EQ(blue, 5);
  EXPECT_EQ(white, 1);
}

}  // namespace
}  // namespace al
