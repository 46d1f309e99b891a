// Fuzz target: PNG decoding (al::DecodePng over libpng): every header, bit depth, colour type,
// interlacing and truncation; the decoded size must match the header and stay under the memory
// limit set here (a small file can claim a huge image: refused from the header, never allocated).
#include <cstdint>

#include "al/core/error.hpp"
#include "al/core/memory_limit.hpp"
#include "al/io/image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  al::SetMemoryLimitBytes(std::uint64_t(256) << 20);
  try {
    const al::PngData png = al::DecodePng(data, size, "fuzz.png");
    if (png.values.size() != std::size_t(png.width) * std::size_t(png.height) * std::size_t(png.channels))
      __builtin_trap();
    if (png.bit_depth != 8 && png.bit_depth != 16) __builtin_trap();
  } catch (const al::Error&) {
  }
  return 0;
}
