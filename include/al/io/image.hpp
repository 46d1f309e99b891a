// PNG images via libpng. Row 0 = top. Interleaved channels.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace al {

struct Image8 {
  int width = 0, height = 0, channels = 0;  // 1, 3 or 4
  std::vector<std::uint8_t> pixels;          // height * width * channels
};

struct Image16 {
  int width = 0, height = 0;                 // single channel
  std::vector<std::uint16_t> pixels;
};

// Writers are atomic and throw al::Error naming the file.
void WritePng8(const std::string& path, const Image8& image);
void WritePng16(const std::string& path, const Image16& image);

// Reads any PNG (1-16 bit, grey/RGB/palette/alpha). Values are returned at their native depth
// in `values` (0..2^depth-1), channels as stored after palette expansion; `bit_depth` tells 8 or 16.
// Sub-8-bit grey is scaled to 8 bits (1-bit 1 -> 255, 4-bit v -> 17v); palette images become RGB,
// or RGBA when they carry a tRNS chunk; a tRNS chunk of grey/RGB images is ignored.
// Corrupt or truncated files throw al::Error naming the file.
struct PngData {
  int width = 0, height = 0, channels = 0, bit_depth = 8;
  std::vector<std::uint16_t> values;  // height * width * channels
};
PngData ReadPng(const std::string& path);
// The same from bytes in memory (fuzzing); `name` prefixes errors. The decoded size is checked
// against the memory limit (al/core/memory_limit.hpp) from the header, before decoding.
PngData DecodePng(const void* data, std::size_t size, const std::string& name);

}  // namespace al
