// .npy reader/writer: round trips, every supported dtype written by hand, float16 known values,
// header variants (v2.0/v3.0, key order, whitespace).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "al/core/error.hpp"
#include "al/io/npy.hpp"
#include "test_data.hpp"

namespace {

// Builds a .npy image by hand (independent of the library's writer).
std::string RawNpy(const std::string& dict, const std::string& data, int major = 1, std::size_t align = 64) {
  const std::size_t pre = major == 1 ? 10 : 12;
  std::string h = dict;
  std::size_t total = pre + h.size() + 1;
  h.append((total + align - 1) / align * align - total, ' ');
  h += '\n';
  std::string out("\x93NUMPY", 6);
  out += static_cast<char>(major);
  out += '\0';
  const std::size_t len = h.size();
  out += static_cast<char>(len & 0xff);
  out += static_cast<char>((len >> 8) & 0xff);
  if (major != 1) {
    out += static_cast<char>((len >> 16) & 0xff);
    out += static_cast<char>((len >> 24) & 0xff);
  }
  return out + h + data;
}

template <typename T>
std::string Bytes(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

std::string Save(const std::filesystem::path& dir, const std::string& name, const std::string& bytes) {
  const std::string p = (dir / name).string();
  std::ofstream(p, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return p;
}

TEST(NpyRoundTrip, WritersReadBackEveryValueAndShape) {
  const auto dir = al::test::TempDir();
  const std::vector<float> f = {1.5f, -0.0f, std::numeric_limits<float>::infinity(), 3e-38f, 7.f, 8.f};
  al::WriteNpy((dir / "f.npy").string(), f, {2, 3});
  auto a = al::ReadNpy((dir / "f.npy").string());
  EXPECT_EQ(a.descr, "f4");
  EXPECT_EQ(a.shape, (std::vector<std::int64_t>{2, 3}));
  const auto back = a.ToFloat();
  ASSERT_EQ(back.size(), f.size());
  for (std::size_t i = 0; i < f.size(); ++i) EXPECT_EQ(std::memcmp(&back[i], &f[i], 4), 0) << i;

  const std::vector<double> d = {1e300, -2.5, 0.1};
  al::WriteNpy((dir / "d.npy").string(), d, {3});
  auto ad = al::ReadNpy((dir / "d.npy").string());
  EXPECT_EQ(ad.descr, "f8");
  EXPECT_EQ(ad.ToDouble(), d);

  const std::vector<std::int32_t> i4 = {-2147483647 - 1, 0, 2147483647};
  al::WriteNpy((dir / "i4.npy").string(), i4, {3, 1});
  auto a4 = al::ReadNpy((dir / "i4.npy").string());
  EXPECT_EQ(a4.descr, "i4");
  EXPECT_EQ(a4.ToInt64(), (std::vector<std::int64_t>{-2147483648LL, 0, 2147483647LL}));

  const std::vector<std::int64_t> i8 = {std::numeric_limits<std::int64_t>::min(), 5, (1LL << 60) + 1};
  al::WriteNpy((dir / "i8.npy").string(), i8, {3});
  EXPECT_EQ(al::ReadNpy((dir / "i8.npy").string()).ToInt64(), i8);

  const std::vector<bool> b = {true, false, false, true, true};
  al::WriteNpyBool((dir / "b.npy").string(), b);
  auto ab = al::ReadNpy((dir / "b.npy").string());
  EXPECT_TRUE(ab.is_bool());
  EXPECT_EQ(ab.ToInt64(), (std::vector<std::int64_t>{1, 0, 0, 1, 1}));

  // Empty arrays are legal.
  al::WriteNpy((dir / "e.npy").string(), std::vector<float>{}, {0, 4});
  EXPECT_EQ(al::ReadNpy((dir / "e.npy").string()).size(), 0u);
}

TEST(NpyRoundTrip, WriterHeaderIsVersion1AlignedTo64) {
  const auto dir = al::test::TempDir();
  for (int n : {0, 1, 7, 1000000}) {
    const std::string p = (dir / "x.npy").string();
    al::WriteNpy(p, std::vector<std::int32_t>(static_cast<std::size_t>(n), 3), {n});
    std::ifstream in(p, std::ios::binary);
    std::string head(10, '\0');
    in.read(head.data(), 10);
    EXPECT_EQ(head.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
    const std::size_t len = static_cast<unsigned char>(head[8]) | (static_cast<unsigned char>(head[9]) << 8);
    EXPECT_EQ((10 + len) % 64, 0u) << n;
    std::string dict(len, '\0');
    in.read(dict.data(), static_cast<std::streamsize>(len));
    EXPECT_EQ(dict.back(), '\n');
    EXPECT_NE(dict.find("'shape': (" + std::to_string(n) + ",)"), std::string::npos) << dict;
    EXPECT_EQ(std::filesystem::file_size(p), 10 + len + 4 * static_cast<std::size_t>(n));
  }
}

TEST(NpyRoundTrip, EveryDtypeWrittenByHand) {
  const auto dir = al::test::TempDir();
  struct Case {
    std::string descr, data;
    std::vector<double> expect;
  };
  const std::vector<Case> cases = {
      {"|b1", Bytes(std::vector<std::uint8_t>{0, 1, 1}), {0, 1, 1}},
      {"|u1", Bytes(std::vector<std::uint8_t>{0, 200, 255}), {0, 200, 255}},
      {"|i1", Bytes(std::vector<std::int8_t>{-128, 0, 127}), {-128, 0, 127}},
      {"<i4", Bytes(std::vector<std::int32_t>{-5, 0, 1 << 30}), {-5, 0, 1 << 30}},
      {"<i8", Bytes(std::vector<std::int64_t>{-(1LL << 40), 0, 9}), {-double(1LL << 40), 0, 9}},
      {"<u4", Bytes(std::vector<std::uint32_t>{0, 4000000000u, 1}), {0, 4000000000.0, 1}},
      {"<u8", Bytes(std::vector<std::uint64_t>{0, 1ULL << 50, 1}), {0, double(1ULL << 50), 1}},
      {"<f2", Bytes(std::vector<std::uint16_t>{0x3c00, 0xc000, 0x7bff}), {1.0, -2.0, 65504.0}},
      {"<f4", Bytes(std::vector<float>{0.25f, -1e10f, 3.f}), {0.25, double(-1e10f), 3}},
      {"<f8", Bytes(std::vector<double>{0.1, -0.2, 1e-300}), {0.1, -0.2, 1e-300}},
      {"=f8", Bytes(std::vector<double>{0.1, -0.2, 1e-300}), {0.1, -0.2, 1e-300}},
      {"=i4", Bytes(std::vector<std::int32_t>{1, 2, 3}), {1, 2, 3}},
  };
  for (const auto& c : cases) {
    const std::string p = Save(dir, "a.npy", RawNpy("{'descr': '" + c.descr + "', 'fortran_order': False, 'shape': (3,), }", c.data));
    const auto a = al::ReadNpy(p);
    EXPECT_EQ(a.descr, c.descr.substr(1)) << c.descr;
    ASSERT_EQ(a.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(a.At(i), c.expect[i]) << c.descr << " " << i;
    const auto dv = a.ToDouble();
    EXPECT_EQ(dv, c.expect) << c.descr;
    if (a.is_integer() || a.is_bool()) {
      const auto iv = a.ToInt64();
      for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(static_cast<double>(iv[i]), c.expect[i]) << c.descr;
    } else {
      EXPECT_THROW(a.ToInt64(), al::Error) << c.descr;
    }
  }
}

TEST(NpyRoundTrip, Float16KnownValues) {
  EXPECT_EQ(al::HalfToFloat(0x0000), 0.0f);
  EXPECT_TRUE(std::signbit(al::HalfToFloat(0x8000)));
  EXPECT_EQ(al::HalfToFloat(0x3c00), 1.0f);
  EXPECT_EQ(al::HalfToFloat(0x3555), 0.333251953125f);
  EXPECT_EQ(al::HalfToFloat(0xc400), -4.0f);
  EXPECT_EQ(al::HalfToFloat(0x7bff), 65504.0f);
  EXPECT_EQ(al::HalfToFloat(0x0400), std::ldexp(1.0f, -14));   // smallest normal
  EXPECT_EQ(al::HalfToFloat(0x0001), std::ldexp(1.0f, -24));   // smallest subnormal
  EXPECT_EQ(al::HalfToFloat(0x03ff), std::ldexp(1023.0f, -24)); // largest subnormal
  EXPECT_EQ(al::HalfToFloat(0x7c00), std::numeric_limits<float>::infinity());
  EXPECT_EQ(al::HalfToFloat(0xfc00), -std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::isnan(al::HalfToFloat(0x7e00)));
  // Every finite half value: independent formula (-1)^s * 2^(e-15) * (1 + m/1024).
  for (std::uint32_t h = 0; h < 0x10000; ++h) {
    const std::uint32_t e = (h >> 10) & 31, m = h & 1023;
    if (e == 31) continue;
    double v = e == 0 ? std::ldexp(double(m), -24) : std::ldexp(1.0 + m / 1024.0, int(e) - 15);
    if (h & 0x8000) v = -v;
    ASSERT_EQ(static_cast<double>(al::HalfToFloat(static_cast<std::uint16_t>(h))), v) << h;
  }
}

TEST(NpyRoundTrip, HeaderVariantsVersion2And3KeyOrderWhitespace) {
  const auto dir = al::test::TempDir();
  const std::string data = Bytes(std::vector<float>{1, 2, 3, 4, 5, 6});
  const std::vector<std::string> dicts = {
      "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }",
      "{'shape': (2, 3), 'fortran_order': False, 'descr': '<f4'}",
      "{ \"fortran_order\" :False,'shape':(2,3),'descr':'<f4' , }",
      "{'descr': '<f4', 'fortran_order': False, 'shape': (2L, 3L), }",
      "{'descr': '<f4', 'fortran_order': False, 'shape': [2, 3]}",
  };
  for (int major : {1, 2, 3})
    for (const auto& d : dicts) {
      const std::string p = Save(dir, "v.npy", RawNpy(d, data, major, major == 1 ? 16 : 64));
      const auto a = al::ReadNpy(p);
      EXPECT_EQ(a.shape, (std::vector<std::int64_t>{2, 3})) << major << " " << d;
      EXPECT_EQ(a.ToFloat(), (std::vector<float>{1, 2, 3, 4, 5, 6})) << major << " " << d;
    }
  // A version 2.0 header longer than 65535 bytes (its reason to exist).
  const std::string big = "{'descr': '<f4', 'fortran_order': False, 'shape': (6,), " + std::string(70000, ' ') + "}";
  const auto a = al::ReadNpy(Save(dir, "big.npy", RawNpy(big, data, 2)));
  EXPECT_EQ(a.size(), 6u);
  EXPECT_EQ(a.ToFloat()[5], 6.0f);
}

}  // namespace
