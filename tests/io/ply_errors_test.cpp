// Bad PLY input: every case throws al::Error "<file>: <problem>"; feature prefix rules; NaN/Inf.
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/io/ply.hpp"
#include "test_data.hpp"

namespace al {
namespace {

const char* kXyzs = "property float x\nproperty float y\nproperty float z\n"
                    "property float scale_0\nproperty float scale_1\nproperty float scale_2\n";

std::string AsciiPly(const std::string& props, const std::string& count, const std::string& body) {
  return "ply\nformat ascii 1.0\nelement vertex " + count + "\n" + props + "end_header\n" + body;
}

// Returns the al::Error message, or "" if no error was thrown.
std::string ErrorOf(const std::string& bytes, const PlyReadOptions& options = {}) {
  try {
    ReadPlyFromMemory(bytes.data(), bytes.size(), "mem.ply", options);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(PlyErrors, EveryBadInputThrowsAnErrorNamingTheFile) {
  std::string binary_header = "ply\nformat binary_little_endian 1.0\nelement vertex 2\n" + std::string(kXyzs) + "end_header\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "empty"},
      {"plx\n", "magic"},
      {"ply\nelement vertex 1\n" + std::string(kXyzs) + "end_header\n1 2 3 4 5 6\n", "format"},
      {"ply\nformat ascii\nelement vertex 1\n" + std::string(kXyzs) + "end_header\n", "format"},
      {"ply\nformat binary_middle_endian 1.0\nelement vertex 0\nend_header\n", "format"},
      {"ply\nformat ascii 2.0\nelement vertex 0\nend_header\n", "version"},
      {"ply\nformat ascii 1.0\nelement vertex 1\n" + std::string(kXyzs), "end_header"},
      {"ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", "element"},
      {"ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\nend_header\n", "element"},
      {"ply\nformat ascii 1.0\nproperty float x\nend_header\n", "before any element"},
      {AsciiPly("property half x\n", "1", "1\n"), "unknown property type"},
      {AsciiPly("property float x\nproperty float y\n", "1", "1 2\n"), "incomplete position"},
      {AsciiPly("property float y\n", "1", "1\n"), "missing property 'x'"},
      {AsciiPly("property float a\n", "1", "1\n"), "missing required"},
      {AsciiPly("property float x\nproperty float y\nproperty float z\n", "1", "1 2 3\n"), "scale_0"},
      {AsciiPly(std::string(kXyzs) + "property list uchar int idx\n", "1", "1 2 3 4 5 6 1 0\n"), "list property"},
      {AsciiPly(std::string(kXyzs) + "property float x\n", "1", "1 2 3 4 5 6 7\n"), "duplicate property"},
      {AsciiPly(kXyzs, "2", "1 2 3 4 5 6\n"), "truncated"},
      {AsciiPly(kXyzs, "1", "1 2 3 4 5\n"), "expected 6"},
      {AsciiPly(kXyzs, "1", "1 2 abc 4 5 6\n"), "non-numeric"},
      {AsciiPly(kXyzs, "1", "1 2 3e 4 5 6\n"), "non-numeric"},
      {AsciiPly(kXyzs, "1000", "1 2 3 4 5 6\n"), "truncated"},
      {binary_header + std::string(47, '\0'), "truncated"},
      {AsciiPly(std::string(kXyzs) + "property float f_rest_0\n", "1", "1 2 3 4 5 6 7\n"), "f_rest"},
      {AsciiPly(std::string(kXyzs) + "property float f_dc_0\n", "1", "1 2 3 4 5 6 7\n"), "incomplete f_dc"},
      {"ply\nformat ascii 1.0\nelement face 1\nproperty float a\nend_header\n1\n", "no 'element vertex'"},
      {"ply\nformat ascii 1.0\nelement vertex 1\n" + std::string(kXyzs) + "bogus line\nend_header\n", "unexpected"},
      {"ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar int v\nelement vertex 1\n" +
           std::string(kXyzs) + "end_header\n" + std::string(64, '\0'),
       "cannot skip"},
  };
  for (const auto& [bytes, what] : cases) {
    const std::string message = ErrorOf(bytes);
    EXPECT_EQ(message.rfind("mem.ply: ", 0), 0u) << "no error or unnamed for case '" << what << "': " << message;
    EXPECT_NE(message.find(what), std::string::npos) << "'" << message << "' should mention '" << what << "'";
  }
}

TEST(PlyErrors, RequiredRenderColumnsAndOptionalScales) {
  const std::string xyz = AsciiPly("property float x\nproperty float y\nproperty float z\n", "1", "1 2 3\n");
  PlyReadOptions relaxed;
  relaxed.require_scales = false;
  EXPECT_EQ(ErrorOf(xyz, relaxed), "");
  const Scene s = ReadPlyFromMemory(xyz.data(), xyz.size(), "xyz.ply", relaxed);
  EXPECT_FALSE(s.has_scales);
  EXPECT_EQ(s.means(0, 2), 3.0f);
  PlyReadOptions render;
  render.require_render_columns = true;
  EXPECT_NE(ErrorOf(AsciiPly(kXyzs, "1", "1 2 3 4 5 6\n"), render).find("opacity"), std::string::npos);
}

TEST(PlyErrors, ElementsBeforeVertexAreSkippedWhenFixedSize) {
  // Binary: a fixed-size element before the vertex element is skipped by its byte size.
  std::string bytes = "ply\nformat binary_little_endian 1.0\nelement camera 2\nproperty double f\nproperty uchar k\n"
                      "element vertex 1\n" + std::string(kXyzs) + "end_header\n";
  bytes += std::string(18, '\x7f');
  const float v[6] = {1, 2, 3, 4, 5, 6};
  bytes.append(reinterpret_cast<const char*>(v), sizeof v);
  const Scene s = ReadPlyFromMemory(bytes.data(), bytes.size(), "cam.ply");
  EXPECT_EQ(s.means(0, 0), 1.0f);
  EXPECT_EQ(s.log_scales(0, 2), 6.0f);
  // ASCII: one line per record of the preceding element.
  const std::string ascii = "ply\nformat ascii 1.0\nelement camera 1\nproperty float f\nelement vertex 1\n" +
                            std::string(kXyzs) + "end_header\n9\n1 2 3 4 5 6\n";
  EXPECT_EQ(ReadPlyFromMemory(ascii.data(), ascii.size(), "a.ply").means(0, 1), 2.0f);
}

TEST(PlyFeatures, AutoPrefixOrderExplicitPrefixAndNone) {
  const std::string props = std::string(kXyzs) +
                            "property float obj_dc_1\nproperty float semantic_1\nproperty float obj_dc_0\n"
                            "property float semantic_0\nproperty float feat_0\n";
  const std::string ply = AsciiPly(props, "1", "1 2 3 4 5 6 11 21 10 20 30\n");
  const Scene a = ReadPlyFromMemory(ply.data(), ply.size(), "f.ply");
  EXPECT_EQ(a.feature_prefix, "semantic_");  // semantic_ before obj_dc_ regardless of file position
  ASSERT_EQ(a.features.cols(), 2);
  EXPECT_EQ(a.features(0, 0), 20.0f);  // ordered by the integer, not by file position
  EXPECT_EQ(a.features(0, 1), 21.0f);
  PlyReadOptions o;
  o.feature_prefix = "obj_dc_";
  const Scene b = ReadPlyFromMemory(ply.data(), ply.size(), "f.ply", o);
  EXPECT_EQ(b.features(0, 0), 10.0f);
  EXPECT_EQ(b.features(0, 1), 11.0f);
  o.feature_prefix = "none";
  EXPECT_EQ(ReadPlyFromMemory(ply.data(), ply.size(), "f.ply", o).features.size(), 0);
  o.feature_prefix = "nothing_";
  EXPECT_NE(ErrorOf(ply, o).find("no feature properties"), std::string::npos);
  // Without features, auto gives an empty matrix and prefix.
  const std::string plain = AsciiPly(kXyzs, "1", "1 2 3 4 5 6\n");
  const Scene c = ReadPlyFromMemory(plain.data(), plain.size(), "p.ply");
  EXPECT_EQ(c.features.size(), 0);
  EXPECT_EQ(c.feature_prefix, "");
}

TEST(PlyFeatures, GapsAndDuplicateIndicesAreErrors) {
  const std::string gap = AsciiPly(std::string(kXyzs) + "property float semantic_0\nproperty float semantic_2\n", "1",
                                   "1 2 3 4 5 6 7 8\n");
  EXPECT_NE(ErrorOf(gap).find("gap in semantic_"), std::string::npos) << ErrorOf(gap);
  const std::string dup = AsciiPly(std::string(kXyzs) + "property float feat_0\nproperty float feat_00\n", "1",
                                   "1 2 3 4 5 6 7 8\n");
  EXPECT_NE(ErrorOf(dup).find("duplicate property index feat_0"), std::string::npos) << ErrorOf(dup);
  const std::string rest_gap = AsciiPly(std::string(kXyzs) + "property float f_rest_1\n", "1", "1 2 3 4 5 6 7\n");
  EXPECT_NE(ErrorOf(rest_gap).find("gap in f_rest_"), std::string::npos) << ErrorOf(rest_gap);
}

TEST(PlyNonFinite, NanAndInfLoadAndAreCounted) {
  const std::string props = std::string(kXyzs) + "property float opacity\nproperty float semantic_0\n";
  const std::string ply = AsciiPly(props, "4",
                                   "1 2 3 0 0 0 0 1\n"
                                   "nan 2 inf 0 0 0 0 1\n"
                                   "1 2 3 -inf 0 0 nan 1\n"
                                   "1 2 3 0 0 0 0 inf\n");
  const Scene s = ReadPlyFromMemory(ply.data(), ply.size(), "nan.ply");
  EXPECT_TRUE(std::isnan(s.means(1, 0)));
  EXPECT_EQ(s.means(1, 2), std::numeric_limits<float>::infinity());
  const NonFiniteCounts c = CountNonFinite(s);
  EXPECT_EQ(c.means, 2u);
  EXPECT_EQ(c.scales, 1u);
  EXPECT_EQ(c.opacities, 1u);
  EXPECT_EQ(c.features, 1u);
  EXPECT_EQ(c.gaussians_with_any, 2u);  // features are not standard parameters
  EXPECT_EQ(FiniteMask(s), (std::vector<bool>{true, false, false, true}));
  const SceneSummary summary = SummarizeScene(s);
  EXPECT_EQ(summary.nonfinite.gaussians_with_any, 2u);
  EXPECT_EQ(summary.bbox_min[0], 1.0f);  // the NaN row is left out of the box
}

TEST(PlyReadScene, DispatchesByExtension) {
  const auto dir = test::TempDir();
  const std::string ply = AsciiPly(kXyzs, "1", "1 2 3 4 5 6\n");
  std::ofstream(dir / "a.PLY", std::ios::binary) << ply;
  EXPECT_EQ(ReadScene((dir / "a.PLY").string()).size(), 1u);
  std::ofstream(dir / "a.txt") << ply;
  EXPECT_THROW(ReadScene((dir / "a.txt").string()), Error);
  try {
    ReadPly((dir / "missing.ply").string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.ply: "), std::string::npos);
  }
}

}  // namespace
}  // namespace al
