// .npy reader: every bad input is an al::Error "<path>: <problem>", never a crash.
#include <gtest/gtest.h>

#include <fstream>

#include "al/core/error.hpp"
#include "al/io/npy.hpp"
#include "test_data.hpp"

namespace {

std::string RawNpy(const std::string& dict, const std::string& data, int major = 1) {
  const std::size_t pre = major == 1 ? 10 : 12;
  std::string h = dict;
  const std::size_t total = pre + h.size() + 1;
  h.append((total + 63) / 64 * 64 - total, ' ');
  h += '\n';
  std::string out("\x93NUMPY", 6);
  out += static_cast<char>(major);
  out += '\0';
  out += static_cast<char>(h.size() & 0xff);
  out += static_cast<char>(h.size() >> 8);
  if (major != 1) out += std::string(2, '\0');
  return out + h + data;
}

// Expects an al::Error whose message starts with the path and contains `needle`.
void ExpectError(const std::string& bytes, const std::string& needle) {
  const auto dir = al::test::TempDir();
  const std::string p = (dir / "bad.npy").string();
  std::ofstream(p, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  try {
    al::ReadNpy(p);
    FAIL() << "no error for " << needle;
  } catch (const al::Error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(p + ": ", 0), 0u) << msg;
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
  }
}

std::string Dict(const std::string& descr, const std::string& order, const std::string& shape) {
  return "{'descr': " + descr + ", 'fortran_order': " + order + ", 'shape': " + shape + ", }";
}

const std::string k12(12, '\0');

// A 10-byte preamble (magic, version, header length 16) and 16 spaces of header. Appended, not
// `std::string + std::string`: GCC 12 warns falsely (-Warray-bounds) on that at -O1.
std::string PaddedHeader(const char (&preamble)[11]) {
  std::string s(preamble, 10);
  s.append(16, ' ');
  return s;
}

TEST(NpyErrors, BadMagicAndTruncatedHeaders) {
  ExpectError("", "too short");
  ExpectError("PK\x03\x04 this is a zip file, a torch .pt maybe", "bad magic");
  ExpectError(PaddedHeader("\x93NUMPX\x01\x00\x10\x00"), "bad magic");
  ExpectError(std::string("\x93NUMPY\x01\x00\xff\x00{'descr'", 17), "truncated");
  ExpectError(PaddedHeader("\x93NUMPY\x04\x00\x10\x00"), "version 4");
}

TEST(NpyErrors, UnsupportedDtypes) {
  ExpectError(RawNpy(Dict("'>f4'", "False", "(3,)"), k12), "big-endian");
  ExpectError(RawNpy(Dict("'>i8'", "False", "(3,)"), k12), "big-endian");
  ExpectError(RawNpy(Dict("'|O'", "False", "(3,)"), k12), "object");
  ExpectError(RawNpy(Dict("'<U4'", "False", "(3,)"), k12), "string");
  ExpectError(RawNpy(Dict("'|S4'", "False", "(3,)"), k12), "string");
  ExpectError(RawNpy(Dict("[('a', '<f4'), ('b', '<i4')]", "False", "(3,)"), std::string(24, '\0')), "structured");
  ExpectError(RawNpy(Dict("'<c8'", "False", "(3,)"), std::string(24, '\0')), "unsupported dtype");
  ExpectError(RawNpy(Dict("'<i2'", "False", "(3,)"), k12), "unsupported dtype");
  ExpectError(RawNpy(Dict("'|f4'", "False", "(3,)"), k12), "unsupported dtype");
}

TEST(NpyErrors, FortranOrderScalarAndShortData) {
  ExpectError(RawNpy(Dict("'<f4'", "True", "(3,)"), k12), "fortran_order");
  ExpectError(RawNpy(Dict("'<f4'", "False", "()"), std::string(4, '\0')), "scalar");
  ExpectError(RawNpy(Dict("'<f4'", "False", "(4,)"), k12), "truncated");
  ExpectError(RawNpy(Dict("'<f8'", "False", "(1000, 1000)"), k12), "truncated");
  // Shapes whose product overflows 64 bits must not wrap around to "small enough".
  ExpectError(RawNpy(Dict("'<f4'", "False", "(4294967296, 4294967296, 16)"), k12), "truncated");
  ExpectError(RawNpy(Dict("'<f4'", "False", "(-3,)"), k12), "non-negative");
}

TEST(NpyErrors, MalformedDicts) {
  ExpectError(RawNpy("{'descr': '<f4', 'shape': (3,), }", k12), "missing");
  ExpectError(RawNpy("{'descr': '<f4', 'fortran_order': False, 'shape': (3,)", k12), "bad .npy header");
  ExpectError(RawNpy("['descr', '<f4']", k12), "bad .npy header");
  ExpectError(RawNpy("{'descr': '<f4', 'fortran_order': 0, 'shape': (3,)}", k12), "fortran_order");
  ExpectError(RawNpy("{'descr': '<f4', 'fortran_order': False, 'shape': (3, 'a')}", k12), "shape");
  ExpectError(RawNpy("{'descr': '<f4', 'fortran_order': False, 'shape': (99999999999999999999999,)}", k12),
              "too large");
  ExpectError(RawNpy("{'descr': '<f4', 'fortran_order': False, 'shape': " + std::string(100, '(') + "}", k12),
              "bad .npy header");
}

TEST(NpyErrors, MissingFileAndWriterShapeMismatch) {
  const auto dir = al::test::TempDir();
  EXPECT_THROW(al::ReadNpy((dir / "absent.npy").string()), al::Error);
  EXPECT_THROW(al::ReadNpy(dir.string()), al::Error);
  EXPECT_THROW(al::WriteNpy((dir / "w.npy").string(), std::vector<float>{1, 2, 3}, {2, 2}), al::Error);
  EXPECT_THROW(al::WriteNpy((dir / "w.npy").string(), std::vector<float>{1}, {}), al::Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "w.npy"));
}

}  // namespace
