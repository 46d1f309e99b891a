// NumPy .npy reading/writing (FORMATS.md §3): versions 1-3, C order, little-endian dtypes
// |b1 |u1 |i1 <i4 <i8 <u4 <u8 <f2 <f4 <f8.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace al {

struct NpyArray {
  std::string descr;                 // normalised: "b1","u1","i1","i4","i8","u4","u8","f2","f4","f8"
  std::vector<std::int64_t> shape;
  std::size_t item_size = 0;
  std::shared_ptr<const void> owner; // keeps the mapping/buffer alive
  const std::uint8_t* data = nullptr;// prod(shape) * item_size bytes

  std::size_t size() const;          // number of elements
  bool is_float() const { return descr[0] == 'f'; }
  bool is_integer() const { return descr[0] == 'i' || descr[0] == 'u'; }
  bool is_bool() const { return descr == "b1"; }
  // Element i converted (float16 handled).
  double At(std::size_t i) const;
  std::vector<float> ToFloat() const;
  std::vector<double> ToDouble() const;
  std::vector<std::int64_t> ToInt64() const;  // integer/bool dtypes only; throws otherwise
};

// Memory-maps and validates; throws al::Error naming the file on any problem.
NpyArray ReadNpy(const std::string& path);

// Parses an in-memory .npy image (used by ReadNpy and the fuzz target). `owner` keeps `bytes`
// alive and is stored in the result; `name` prefixes error messages. Throws al::Error.
NpyArray ParseNpy(std::shared_ptr<const void> owner, const std::uint8_t* bytes, std::size_t size,
                  const std::string& name);

// IEEE 754 binary16 -> float (exact for every value: subnormals, infinities, NaN).
float HalfToFloat(std::uint16_t h);

// Writers (version 1.0, C order, 64-byte aligned header), atomic.
void WriteNpy(const std::string& path, const std::vector<float>& data, const std::vector<std::int64_t>& shape);
void WriteNpy(const std::string& path, const std::vector<double>& data, const std::vector<std::int64_t>& shape);
void WriteNpy(const std::string& path, const std::vector<std::int32_t>& data, const std::vector<std::int64_t>& shape);
void WriteNpy(const std::string& path, const std::vector<std::int64_t>& data, const std::vector<std::int64_t>& shape);
void WriteNpyBool(const std::string& path, const std::vector<bool>& data);  // shape (N,)

}  // namespace al
