// Fuzz target: the sweep manifest (`sweep --manifest`: a JSON list of scenes with relative paths)
// and the grid syntaxes (`--grid` of sweep and compare). The first byte picks the parser.
#include <cstdint>
#include <string>

#include "al/core/error.hpp"
#include "al/refine/compare.hpp"
#include "al/refine/sweep.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const al::RefineOptions base;
  try {
    switch (data[0] % 3) {
      case 0: {
        for (const auto& s : al::ParseSweepManifest(text, "/fuzz/manifest.json", base))
          if (s.name.empty()) __builtin_trap();
        break;
      }
      case 1: {
        const al::SweepGrid g = al::ParseSweepGrid(text, base);
        if (g.size() < 1000000) (void)al::EnumeratePoints(g);
        break;
      }
      default:
        (void)al::SolverGridToString(al::ParseSolverGrid(text));
    }
  } catch (const al::Error&) {
  }
  return 0;
}
