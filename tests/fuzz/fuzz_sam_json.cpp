// Fuzz target: SAM segment lists (dense arrays, COCO RLE strings and count lists, legacy merged
// maps), GroundedSAM JSON and the compressed-RLE string decoder. The first byte picks the parser.
// The harness compiles the two metrics sources it exercises because the fuzz targets link al_io
// only (tests/fuzz/CMakeLists.txt); they depend on nothing else of al_metrics.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "al/core/error.hpp"
#include "al/metrics/mask_io.hpp"
#include "src/metrics/mask.cpp"
#include "src/metrics/mask_io.cpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    switch (data[0] % 3) {
      case 0: {
        std::size_t on = 0;
        for (const auto& [stem, masks] : al::metrics::ParseSamJsonText(text, "fuzz.json"))
          for (const auto& m : masks) {
            // Every mask must be consistent with its declared size.
            if (m.bits.size() != std::size_t(m.width) * std::size_t(m.height)) __builtin_trap();
            on += m.Count();
          }
        (void)on;
        break;
      }
      case 1: {
        const auto g = al::metrics::ParseGroundedSamText(text, "bear", "fuzz.json");
        if (g.mask.pixels.size() != std::size_t(g.mask.width) * std::size_t(g.mask.height)) __builtin_trap();
        break;
      }
      default: {
        const auto counts = al::metrics::DecodeCocoRleString(text, "fuzz.rle");
        std::int64_t total = 0;
        for (auto c : counts) total += c < 0 || c > (1 << 20) ? 0 : c;
        if (total > 0 && total <= (1 << 20)) (void)al::metrics::MaskFromRleCounts(counts, 1, int(total), "fuzz.rle");
        break;
      }
    }
  } catch (const al::Error&) {
  }
  return 0;
}
