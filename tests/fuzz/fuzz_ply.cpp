// Fuzz target: PLY reader. al::Error is the expected outcome for bad input; anything else
// (crash, other exception, sanitizer report) is a bug.
#include <cstdint>

#include "al/core/error.hpp"
#include "al/io/ply.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  for (const char* prefix : {"auto", "none"}) {
    al::PlyReadOptions options;
    options.feature_prefix = prefix;
    options.require_scales = false;
    try {
      const al::Scene scene = al::ReadPlyFromMemory(data, size, "fuzz.ply", options);
      (void)al::CountNonFinite(scene);
      (void)al::SummarizeScene(scene);
    } catch (const al::Error&) {
    }
  }
  return 0;
}
