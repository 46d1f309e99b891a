// Fuzz target: the output-set manifest reader behind `al-refine info --verify` (a report.json an
// attacker controls): entries must stay inside the folder and never open special files.
#include <cstdint>
#include <filesystem>
#include <string>

#include "al/core/output_set.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::temp_directory_path() / "al_fuzz_output_manifest";
    std::filesystem::create_directories(d);
    return d;
  }();
  const std::string text(reinterpret_cast<const char*>(data), size);
  const al::OutputSetStatus s = al::VerifyManifest(text, dir);
  if (s.state != "complete" && s.state != "extended" && s.state != "incomplete" && s.state != "not_a_set")
    __builtin_trap();
  (void)s.ToJson().dump();
  return 0;
}
