// PNG: 8/16-bit round trips, and files built by hand with zlib (independent of libpng's encoder):
// 1-bit grey, palette with and without transparency, grey+alpha; corrupt files are al::Error.
#include <gtest/gtest.h>
#include <zlib.h>

#include <fstream>
#include <random>

#include "al/core/error.hpp"
#include "al/io/image.hpp"
#include "test_data.hpp"

namespace {

void Put32(std::string& s, std::uint32_t v) {
  for (int k = 3; k >= 0; --k) s += static_cast<char>((v >> (8 * k)) & 0xff);
}

std::string Chunk(const std::string& type, const std::string& data) {
  std::string c;
  Put32(c, static_cast<std::uint32_t>(data.size()));
  const std::string body = type + data;
  c += body;
  Put32(c, static_cast<std::uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))));
  return c;
}

// A PNG from already packed rows (each row without its filter byte).
std::string HandPng(int w, int h, int depth, int color, const std::vector<std::string>& rows,
                    const std::string& plte = "", const std::string& trns = "") {
  std::string ihdr;
  Put32(ihdr, static_cast<std::uint32_t>(w));
  Put32(ihdr, static_cast<std::uint32_t>(h));
  ihdr += static_cast<char>(depth);
  ihdr += static_cast<char>(color);
  ihdr += std::string(3, '\0');
  std::string raw;
  for (const auto& r : rows) raw += '\0' + r;  // filter type 0 (None)
  uLongf len = compressBound(static_cast<uLong>(raw.size()));
  std::string z(len, '\0');
  compress(reinterpret_cast<Bytef*>(z.data()), &len, reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()));
  z.resize(len);
  std::string png("\x89PNG\r\n\x1a\n", 8);
  png += Chunk("IHDR", ihdr);
  if (!plte.empty()) png += Chunk("PLTE", plte);
  if (!trns.empty()) png += Chunk("tRNS", trns);
  png += Chunk("IDAT", z);
  png += Chunk("IEND", "");
  return png;
}

std::string Save(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return p.string();
}

TEST(ImagePng, Png8RoundTripOneThreeFourChannels) {
  const auto dir = al::test::TempDir();
  std::mt19937 rng(7);
  for (int ch : {1, 3, 4}) {
    al::Image8 img;
    img.width = 37;
    img.height = 11;
    img.channels = ch;
    img.pixels.resize(static_cast<std::size_t>(37 * 11 * ch));
    for (auto& v : img.pixels) v = static_cast<std::uint8_t>(rng());
    img.pixels[0] = 0;
    img.pixels[1] = 255;
    const std::string p = (dir / ("c" + std::to_string(ch) + ".png")).string();
    al::WritePng8(p, img);
    const auto back = al::ReadPng(p);
    EXPECT_EQ(back.width, 37);
    EXPECT_EQ(back.height, 11);
    EXPECT_EQ(back.channels, ch);
    EXPECT_EQ(back.bit_depth, 8);
    ASSERT_EQ(back.values.size(), img.pixels.size());
    for (std::size_t i = 0; i < img.pixels.size(); ++i) ASSERT_EQ(back.values[i], img.pixels[i]) << ch << " " << i;
  }
}

TEST(ImagePng, Png16RoundTrip) {
  const auto dir = al::test::TempDir();
  al::Image16 img;
  img.width = 5;
  img.height = 4;
  img.pixels = {0, 1, 255, 256, 65535, 65534, 4660, 43981, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 40000};
  const std::string p = (dir / "d.png").string();
  al::WritePng16(p, img);
  const auto back = al::ReadPng(p);
  EXPECT_EQ(back.bit_depth, 16);
  EXPECT_EQ(back.channels, 1);
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.height, 4);
  EXPECT_EQ(back.values, img.pixels);
  // 16-bit samples are big-endian in the file: the first IDAT row starts 00 00 00 01 00 ff 01 00 (checked via
  // a hand-built twin that must decode to the same values).
  std::string row0, row1, row2, row3;
  for (int r = 0; r < 4; ++r) {
    std::string& row = r == 0 ? row0 : r == 1 ? row1 : r == 2 ? row2 : row3;
    for (int c = 0; c < 5; ++c) {
      const auto v = img.pixels[static_cast<std::size_t>(r * 5 + c)];
      row += static_cast<char>(v >> 8);
      row += static_cast<char>(v & 0xff);
    }
  }
  const auto hand = al::ReadPng(Save(dir / "hand16.png", HandPng(5, 4, 16, 0, {row0, row1, row2, row3})));
  EXPECT_EQ(hand.values, img.pixels);
}

TEST(ImagePng, OneBitGreyExpandsTo8Bit) {
  const auto dir = al::test::TempDir();
  // 10 px wide: rows pack into 2 bytes, the last 6 bits are padding.
  const std::vector<std::string> rows = {std::string("\xA0\x40", 2), std::string("\xFF\xC0", 2), std::string("\x00\x00", 2)};
  const auto img = al::ReadPng(Save(dir / "bits.png", HandPng(10, 3, 1, 0, rows)));
  EXPECT_EQ(img.width, 10);
  EXPECT_EQ(img.height, 3);
  EXPECT_EQ(img.channels, 1);
  EXPECT_EQ(img.bit_depth, 8);
  const std::vector<std::uint16_t> expect = {255, 0, 255, 0, 0, 0, 0, 0, 0, 255,  //
                                             255, 255, 255, 255, 255, 255, 255, 255, 255, 255,  //
                                             0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(img.values, expect);
  // 4-bit grey: value v becomes v * 17.
  const auto g4 = al::ReadPng(Save(dir / "g4.png", HandPng(3, 1, 4, 0, {std::string("\x0F\x50", 2)})));
  EXPECT_EQ(g4.values, (std::vector<std::uint16_t>{0, 255, 85}));
}

TEST(ImagePng, PaletteExpandedWithAndWithoutTransparency) {
  const auto dir = al::test::TempDir();
  const std::string plte("\x10\x20\x30\xff\x00\x00\x00\x80\x40", 9);  // 3 entries
  // 2-bit indices, 4 px: 0 1 2 1 -> 0b00011001 = 0x19.
  const std::vector<std::string> rows = {std::string("\x19", 1), std::string("\x80", 1)};
  const auto rgb = al::ReadPng(Save(dir / "p.png", HandPng(4, 2, 2, 3, rows, plte)));
  EXPECT_EQ(rgb.channels, 3);
  EXPECT_EQ(rgb.bit_depth, 8);
  const std::vector<std::uint16_t> expect = {0x10, 0x20, 0x30, 0xff, 0, 0, 0, 0x80, 0x40, 0xff, 0, 0,
                                             0, 0x80, 0x40, 0x10, 0x20, 0x30, 0x10, 0x20, 0x30, 0x10, 0x20, 0x30};
  EXPECT_EQ(rgb.values, expect);
  const auto rgba = al::ReadPng(Save(dir / "pt.png", HandPng(4, 2, 2, 3, rows, plte, std::string("\x00\x7f", 2))));
  EXPECT_EQ(rgba.channels, 4);
  ASSERT_EQ(rgba.values.size(), 32u);
  EXPECT_EQ(rgba.values[3], 0);     // entry 0: alpha 0
  EXPECT_EQ(rgba.values[7], 0x7f);  // entry 1: alpha 127
  EXPECT_EQ(rgba.values[11], 255);  // entry 2: beyond tRNS -> opaque
  EXPECT_EQ(rgba.values[8], 0);
  EXPECT_EQ(rgba.values[9], 0x80);
  // Grey + alpha, 8 bit.
  const auto ga = al::ReadPng(Save(dir / "ga.png", HandPng(2, 1, 8, 4, {std::string("\x05\x06\x07\x08", 4)})));
  EXPECT_EQ(ga.channels, 2);
  EXPECT_EQ(ga.values, (std::vector<std::uint16_t>{5, 6, 7, 8}));
}

TEST(ImagePng, CorruptFilesAndBadWritesAreErrors) {
  const auto dir = al::test::TempDir();
  auto expect_error = [](const std::string& p, const std::string& needle) {
    try {
      al::ReadPng(p);
      FAIL() << "no error for " << p;
    } catch (const al::Error& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(p + ": ", 0), 0u) << msg;
      EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    }
  };
  expect_error(Save(dir / "text.png", "hello, not a png"), "signature");
  expect_error((dir / "absent.png").string(), "cannot open");
  const std::string good = HandPng(4, 4, 8, 0, std::vector<std::string>(4, std::string(4, 'x')));
  expect_error(Save(dir / "trunc.png", good.substr(0, good.size() - 30)), "corrupt PNG");
  std::string badcrc = good;
  badcrc[8 + 8 + 13] ^= 1;  // IHDR CRC
  expect_error(Save(dir / "crc.png", badcrc), "corrupt PNG");
  std::string badihdr = HandPng(0, 4, 8, 0, {});
  expect_error(Save(dir / "zero.png", badihdr), "corrupt PNG");
  std::string baddepth = HandPng(4, 1, 3, 0, {std::string(2, '\0')});
  expect_error(Save(dir / "depth.png", baddepth), "corrupt PNG");

  al::Image8 img;
  img.width = 2;
  img.height = 2;
  img.channels = 2;
  img.pixels.assign(8, 0);
  EXPECT_THROW(al::WritePng8((dir / "w.png").string(), img), al::Error);
  img.channels = 3;
  EXPECT_THROW(al::WritePng8((dir / "w.png").string(), img), al::Error);  // wrong buffer size
  al::Image16 d;
  d.width = 0;
  d.height = 3;
  EXPECT_THROW(al::WritePng16((dir / "w.png").string(), d), al::Error);
  EXPECT_THROW(al::WritePng8((dir / "no_such_dir" / "w.png").string(), al::Image8{1, 1, 1, {0}}), al::Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "w.png"));
}

}  // namespace
