// Fuzz target: antimatter15 .splat reader.
#include <cstdint>

#include "al/core/error.hpp"
#include "al/io/ply.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const al::Scene scene = al::ReadSplatFromMemory(data, size, "fuzz.splat");
    (void)al::FiniteMask(scene);
    (void)al::SummarizeScene(scene);
  } catch (const al::Error&) {
  }
  return 0;
}
