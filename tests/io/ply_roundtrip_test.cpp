// PLY reader/writer against files produced by an independent small writer (every format and
// scalar type), plus write -> read round trips.
#include <algorithm>
#include <bit>
#include <limits>
#include <numeric>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/io/ply.hpp"
#include "test_data.hpp"

namespace al {
namespace {

enum class Fmt { kAscii, kLE, kBE };

struct Col {
  std::string name;
  std::string type = "float";
};

// Independent reference writer: values are cast to each column's type and encoded.
std::string MakePly(Fmt fmt, const std::vector<Col>& cols, const std::vector<std::vector<double>>& rows,
                    const std::string& trailer_header = "", const std::string& trailer_data = "") {
  std::ostringstream h;
  h << "ply\nformat " << (fmt == Fmt::kAscii ? "ascii" : fmt == Fmt::kLE ? "binary_little_endian" : "binary_big_endian")
    << " 1.0\ncomment made by the test\nelement vertex " << rows.size() << "\n";
  for (const auto& c : cols) h << "property " << c.type << " " << c.name << "\n";
  h << trailer_header << "end_header\n";
  std::string out = h.str();
  for (const auto& row : rows) {
    for (std::size_t c = 0; c < cols.size(); ++c) {
      const std::string& t = cols[c].type;
      const double v = row[c];
      if (fmt == Fmt::kAscii) {
        char buf[64];
        if (t == "float" || t == "float32") std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(static_cast<float>(v)));
        else if (t == "double" || t == "float64") std::snprintf(buf, sizeof buf, "%.17g", v);
        else std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(v));
        out += buf;
        out += c + 1 < cols.size() ? " " : "\n";
        continue;
      }
      unsigned char bytes[8];
      int size = 0;
      auto put = [&](auto x) {
        size = sizeof(x);
        std::memcpy(bytes, &x, sizeof(x));
      };
      if (t == "char" || t == "int8") put(static_cast<std::int8_t>(v));
      else if (t == "uchar" || t == "uint8") put(static_cast<std::uint8_t>(v));
      else if (t == "short" || t == "int16") put(static_cast<std::int16_t>(v));
      else if (t == "ushort" || t == "uint16") put(static_cast<std::uint16_t>(v));
      else if (t == "int" || t == "int32") put(static_cast<std::int32_t>(v));
      else if (t == "uint" || t == "uint32") put(static_cast<std::uint32_t>(v));
      else if (t == "float" || t == "float32") put(static_cast<float>(v));
      else put(v);
      if ((fmt == Fmt::kBE) == (std::endian::native == std::endian::little)) std::reverse(bytes, bytes + size);
      out.append(reinterpret_cast<const char*>(bytes), static_cast<std::size_t>(size));
    }
  }
  return out + trailer_data;
}

std::string WriteFile(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path.string();
}

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<Col> StandardCols(int rest, int features = 0, const std::string& prefix = "semantic_") {
  std::vector<Col> cols = {{"x"}, {"y"}, {"z"}, {"nx"}, {"ny"}, {"nz"}, {"f_dc_0"}, {"f_dc_1"}, {"f_dc_2"}};
  for (int j = 0; j < rest; ++j) cols.push_back({"f_rest_" + std::to_string(j)});
  cols.push_back({"opacity"});
  for (int k = 0; k < 3; ++k) cols.push_back({"scale_" + std::to_string(k)});
  for (int k = 0; k < 4; ++k) cols.push_back({"rot_" + std::to_string(k)});
  for (int d = 0; d < features; ++d) cols.push_back({prefix + std::to_string(d)});
  return cols;
}

std::vector<std::vector<double>> RandomRows(std::size_t n, std::size_t cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  std::vector<std::vector<double>> rows(n, std::vector<double>(cols));
  for (auto& r : rows)
    for (auto& v : r) v = u(rng);
  return rows;
}

// Checks every standard column of `s` against the rows written with StandardCols(rest, features).
void ExpectMatchesStandard(const Scene& s, const std::vector<std::vector<double>>& rows, int rest, int features) {
  const int k_minus_1 = rest / 3;
  ASSERT_EQ(s.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const Eigen::Index e = static_cast<Eigen::Index>(i);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(s.means(e, c), static_cast<float>(r[c]));
      EXPECT_EQ(s.sh(e, c), static_cast<float>(r[6 + c]));
      EXPECT_EQ(s.log_scales(e, c), static_cast<float>(r[10 + rest + c]));
    }
    for (int j = 0; j < rest; ++j) {
      const int ch = j / k_minus_1, k = j % k_minus_1 + 1;
      EXPECT_EQ(s.sh(e, k * 3 + ch), static_cast<float>(r[9 + j])) << "f_rest_" << j;
    }
    EXPECT_EQ(s.opacity_logits(e), static_cast<float>(r[9 + rest]));
    for (int c = 0; c < 4; ++c) EXPECT_EQ(s.rotations(e, c), static_cast<float>(r[13 + rest + c]));
    for (int d = 0; d < features; ++d) EXPECT_EQ(s.features(e, d), static_cast<float>(r[17 + rest + d]));
  }
}

TEST(PlyRoundTrip, EveryScalarTypeInEveryFormat) {
  const auto dir = test::TempDir();
  const std::vector<std::string> types = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double",
                                          "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  for (Fmt fmt : {Fmt::kAscii, Fmt::kLE, Fmt::kBE}) {
    for (const auto& t : types) {
      const bool is_unsigned = t[0] == 'u';
      const bool is_float = t.find("float") != std::string::npos || t == "double";
      std::vector<Col> cols = {{"x", t}, {"y", t}, {"z", t}, {"scale_0", t}, {"scale_1", t}, {"scale_2", t}};
      std::vector<std::vector<double>> rows;
      for (int i = 0; i < 5; ++i) {
        std::vector<double> r;
        for (int c = 0; c < 6; ++c) {
          double v = (i * 6 + c) % 100 - (is_unsigned ? 0 : 50);
          if (is_float) v += 0.25;  // exactly representable in float32
          r.push_back(v);
        }
        rows.push_back(r);
      }
      const auto path = WriteFile(dir / ("t_" + t + std::to_string(int(fmt)) + ".ply"), MakePly(fmt, cols, rows));
      const Scene s = ReadPly(path);
      ASSERT_EQ(s.size(), 5u) << t;
      for (int i = 0; i < 5; ++i)
        for (int c = 0; c < 3; ++c) {
          EXPECT_EQ(s.means(i, c), static_cast<float>(rows[i][c])) << t << " format " << int(fmt);
          EXPECT_EQ(s.log_scales(i, c), static_cast<float>(rows[i][3 + c])) << t;
        }
      EXPECT_FALSE(s.has_opacity);
      EXPECT_FALSE(s.has_rotations);
      EXPECT_EQ(s.ply->properties.size(), 6u);
    }
  }
}

TEST(PlyRoundTrip, StandardLayoutAllFormatsAndShDegrees) {
  const auto dir = test::TempDir();
  for (int rest : {0, 9, 24, 45}) {
    const auto cols = StandardCols(rest, 4);
    const auto rows = RandomRows(7, cols.size(), 10 + rest);
    for (Fmt fmt : {Fmt::kAscii, Fmt::kLE, Fmt::kBE}) {
      const auto path = WriteFile(dir / ("s" + std::to_string(rest) + "_" + std::to_string(int(fmt)) + ".ply"),
                                  MakePly(fmt, cols, rows));
      const Scene s = ReadPly(path);
      EXPECT_EQ(s.sh_degree, rest == 0 ? 0 : rest == 9 ? 1 : rest == 24 ? 2 : 3);
      EXPECT_EQ(s.sh.cols(), 3 * (s.sh_degree + 1) * (s.sh_degree + 1));
      EXPECT_EQ(s.feature_prefix, "semantic_");
      EXPECT_TRUE(s.has_opacity && s.has_scales && s.has_rotations && s.has_f_dc);
      ExpectMatchesStandard(s, rows, rest, 4);
    }
  }
}

TEST(PlyRoundTrip, ShuffledPropertyOrderAndUnknownPropertiesGiveTheSameScene) {
  const auto dir = test::TempDir();
  const auto cols = StandardCols(24, 3, "obj_dc_");
  const auto rows = RandomRows(9, cols.size(), 3);
  const Scene ref = ReadPly(WriteFile(dir / "ref.ply", MakePly(Fmt::kLE, cols, rows)));
  // Shuffle the columns and add unknown ones (kept in the source, ignored by the Scene).
  std::vector<std::size_t> perm(cols.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(7));
  std::vector<Col> shuffled;
  std::vector<std::vector<double>> srows(rows.size());
  shuffled.push_back({"filter_3D", "double"});
  for (auto& r : srows) r.push_back(42.5);
  for (std::size_t p : perm) {
    shuffled.push_back({cols[p].name, p % 2 ? "double" : "float"});
    for (std::size_t i = 0; i < rows.size(); ++i) srows[i].push_back(rows[i][p]);
  }
  for (Fmt fmt : {Fmt::kAscii, Fmt::kBE}) {
    const Scene s = ReadPly(WriteFile(dir / ("shuf" + std::to_string(int(fmt)) + ".ply"), MakePly(fmt, shuffled, srows)));
    EXPECT_EQ(s.ply->properties.size(), cols.size() + 1);
    EXPECT_EQ(s.ply->properties[0].name, "filter_3D");
    EXPECT_EQ(s.feature_prefix, "obj_dc_");
    ExpectMatchesStandard(s, rows, 24, 3);
    EXPECT_EQ(s.sh, ref.sh);
    EXPECT_EQ(s.features, ref.features);
  }
}

TEST(PlyRoundTrip, FRestIsReorderedFromChannelMajorToCoefficientMajor) {
  const auto dir = test::TempDir();
  const auto cols = StandardCols(45);
  std::vector<std::vector<double>> rows(2, std::vector<double>(cols.size(), 0.0));
  for (int j = 0; j < 45; ++j) rows[1][9 + j] = j;  // f_rest_j = j
  const Scene s = ReadPly(WriteFile(dir / "rest.ply", MakePly(Fmt::kLE, cols, rows)));
  for (int k = 1; k < 16; ++k)
    for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(s.sh(1, k * 3 + ch), float(ch * 15 + (k - 1))) << k << " " << ch;
}

TEST(PlyRoundTrip, GeneratedSceneWritesInriaLayoutAndReadsBackExactly) {
  const auto dir = test::TempDir();
  Scene g;
  const int n = 50;
  g.sh_degree = 2;
  std::mt19937 rng(5);
  std::normal_distribution<float> d;
  g.means = MatX3f::NullaryExpr(n, 3, [&]() { return d(rng); });
  g.log_scales = MatX3f::NullaryExpr(n, 3, [&]() { return d(rng); });
  g.rotations = MatX4f::NullaryExpr(n, 4, [&]() { return d(rng); });
  g.opacity_logits = Eigen::VectorXf::NullaryExpr(n, [&]() { return d(rng); });
  g.sh = RowMatXf::NullaryExpr(n, 27, [&]() { return d(rng); });
  g.features = RowMatXf::NullaryExpr(n, 5, [&]() { return d(rng); });
  const auto path = (dir / "gen.ply").string();
  WritePly(path, g);
  const Scene s = ReadPly(path);
  EXPECT_EQ(s.ply->format, PlySource::Format::kBinaryLittleEndian);
  EXPECT_EQ(s.ply->record_bytes, (17u + 24u + 5u) * 4u);
  EXPECT_EQ(s.ply->properties[3].name, "nx");
  EXPECT_EQ(s.feature_prefix, "semantic_");  // empty prefix -> semantic_
  EXPECT_EQ(s.means, g.means);
  EXPECT_EQ(s.log_scales, g.log_scales);
  EXPECT_EQ(s.rotations, g.rotations);
  EXPECT_EQ(s.opacity_logits, g.opacity_logits);
  EXPECT_EQ(s.sh, g.sh);
  EXPECT_EQ(s.features, g.features);
  EXPECT_EQ(s.sh_degree, 2);
  // Independent check of the channel-major file order: f_rest_{ch*8 + k-1} at float index 9 + j.
  const std::string bytes = ReadBytes(path);
  const std::size_t header = s.ply->header.size();
  float v;
  std::memcpy(&v, bytes.data() + header + s.ply->record_bytes * 3 + (9 + 1 * 8 + 4) * 4, 4);  // ch 1, k 5
  EXPECT_EQ(v, g.sh(3, 5 * 3 + 1));

  // Subset write of the generated scene.
  std::vector<bool> keep(n, false);
  keep[0] = keep[17] = keep[49] = true;
  WritePly(path, g, keep);
  const Scene sub = ReadPly(path);
  ASSERT_EQ(sub.size(), 3u);
  EXPECT_EQ(sub.means.row(1), g.means.row(17));
  EXPECT_EQ(sub.features.row(2), g.features.row(49));
}

TEST(PlyRoundTrip, SubsetOfAsciiAndBigEndianFilesKeepsFormatAndRecords) {
  const auto dir = test::TempDir();
  const auto cols = StandardCols(9, 2);
  const auto rows = RandomRows(6, cols.size(), 11);
  std::vector<bool> keep = {true, false, false, true, true, false};
  for (Fmt fmt : {Fmt::kAscii, Fmt::kBE}) {
    const auto in = WriteFile(dir / ("in" + std::to_string(int(fmt)) + ".ply"), MakePly(fmt, cols, rows));
    const Scene s = ReadPly(in);
    const auto out = (dir / ("out" + std::to_string(int(fmt)) + ".ply")).string();
    WritePly(out, s, keep);
    std::vector<std::vector<double>> kept_rows;
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (keep[i]) kept_rows.push_back(rows[i]);
    // The independent writer produces the same bytes for the kept rows (same header but the count).
    EXPECT_EQ(ReadBytes(out), MakePly(fmt, cols, kept_rows));
    ExpectMatchesStandard(ReadPly(out), kept_rows, 9, 2);
  }
}

TEST(PlyRoundTrip, WriterDropsOtherElementsAndRejectsBadMasks) {
  const auto dir = test::TempDir();
  const auto cols = StandardCols(0);
  const auto rows = RandomRows(4, cols.size(), 2);
  // A face element (list property) after the vertex element.
  std::string face_data;
  for (int f = 0; f < 2; ++f) {
    face_data.push_back(3);
    for (std::int32_t idx : {0, 1, 2}) face_data.append(reinterpret_cast<const char*>(&idx), 4);
  }
  const auto in = WriteFile(dir / "faces.ply",
                            MakePly(Fmt::kLE, cols, rows, "element face 2\nproperty list uchar int vertex_indices\n", face_data));
  const Scene s = ReadPly(in);
  ExpectMatchesStandard(s, rows, 0, 0);
  ASSERT_EQ(s.ply->extra_elements.size(), 1u);
  const auto out = (dir / "out.ply").string();
  WritePly(out, s);
  EXPECT_EQ(ReadBytes(out), MakePly(Fmt::kLE, cols, rows));
  EXPECT_THROW(WritePly(out, s, std::vector<bool>(3, true)), Error);
}

// Binary scenes read from a file keep their records in the file, not in memory: the byte-exact
// writer must still work after the path was replaced (the open file is read), and a file truncated
// in place must give an error and no output rather than garbage.
TEST(PlyRoundTrip, FileBackedRecordsSurviveReplacementAndReportTruncation) {
  const auto dir = test::TempDir();
  const auto cols = StandardCols(9, 2);
  const auto rows = RandomRows(5000, cols.size(), 21);
  const std::string original = MakePly(Fmt::kLE, cols, rows);
  const auto in = WriteFile(dir / "in.ply", original);
  const Scene s = ReadPly(in);
  ASSERT_TRUE(s.ply->vertex_file);
  EXPECT_FALSE(s.ply->vertex_bytes);  // no second copy of the records in memory
  std::filesystem::rename(WriteFile(dir / "other.ply", MakePly(Fmt::kLE, cols, RandomRows(7, cols.size(), 3))), in);
  std::vector<bool> keep(rows.size());
  std::vector<std::vector<double>> kept_rows;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if ((keep[i] = (i % 3 != 1))) kept_rows.push_back(rows[i]);
  const auto out = (dir / "out.ply").string();
  WritePly(out, s, keep);
  EXPECT_EQ(ReadBytes(out), MakePly(Fmt::kLE, cols, kept_rows));

  const auto in2 = WriteFile(dir / "in2.ply", original);
  const Scene t = ReadPly(in2);
  std::filesystem::resize_file(in2, original.size() / 2);  // truncated in place after loading
  const auto out2 = dir / "out2.ply";
  EXPECT_THROW(WritePly(out2.string(), t), Error);
  EXPECT_FALSE(std::filesystem::exists(out2));
}

// Refine reads f_rest and the rotations only to check them: the scene keeps f_dc (degree 0) and no
// rotations, flags the rows with a non-finite value there, and every other column and the finite
// mask equal a full read's.
TEST(PlyRoundTrip, ShRestAndRotationsCheckedNotDecodedFlagNonFiniteRowsAndKeepTheRest) {
  const auto dir = test::TempDir();
  for (int rest : {0, 9, 45}) {
    const auto cols = StandardCols(rest, 4);
    auto rows = RandomRows(6, cols.size(), 20 + rest);
    if (rest > 0) {
      rows[1][9 + rest / 2] = std::nan("");                           // an f_rest value
      rows[4][9 + rest - 1] = std::numeric_limits<double>::infinity();  // the last one
    }
    rows[3][9 + rest + 3] = std::nan("");  // a scale (decoded either way)
    rows[5][13 + rest + 2] = std::nan("");  // rot_2
    for (Fmt fmt : {Fmt::kLE, Fmt::kBE, Fmt::kAscii}) {
      const auto path = WriteFile(dir / ("r" + std::to_string(rest) + "_" + std::to_string(int(fmt)) + ".ply"),
                                  MakePly(fmt, cols, rows));
      PlyReadOptions lean;
      lean.sh_rest = false;
      lean.rotations = false;
      const Scene full = ReadPly(path), s = ReadPly(path, lean);
      const std::string what = "rest " + std::to_string(rest) + " format " + std::to_string(int(fmt));
      EXPECT_EQ(s.sh_degree, 0) << what;
      ASSERT_EQ(s.sh.cols(), 3) << what;
      EXPECT_TRUE(s.sh.leftCols(3) == full.sh.leftCols(3)) << what;
      EXPECT_TRUE(s.means == full.means && s.features == full.features) << what;
      EXPECT_EQ(s.rotations.rows(), 0) << what;
      EXPECT_TRUE(s.has_rotations) << what;
      EXPECT_EQ(s.log_scales.row(2), full.log_scales.row(2)) << what;
      const std::vector<std::uint8_t> want =
          rest > 0 ? std::vector<std::uint8_t>{0, 1, 0, 0, 1, 1} : std::vector<std::uint8_t>{0, 0, 0, 0, 0, 1};
      EXPECT_EQ(s.nonfinite_undecoded, want) << what;
      EXPECT_EQ(FiniteMask(s), FiniteMask(full)) << what;
      EXPECT_EQ(CountNonFinite(s).gaussians_with_any, CountNonFinite(full).gaussians_with_any) << what;
    }
  }
}

}  // namespace
}  // namespace al
