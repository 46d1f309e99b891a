// Fuzz target: camera parsers. Input starting with '[' or '{' goes to the JSON parser (INRIA or
// plain list); otherwise it is split at the first NUL byte into cameras.txt and images.txt.
#include <cstdint>
#include <set>
#include <string>

#include "al/core/error.hpp"
#include "al/io/cameras.hpp"

namespace {

// ReadCameras' renaming: every name must come out safe as a file name and unique.
void CheckNames(std::vector<al::Camera> cameras) {
  al::MakeViewNamesSafe(cameras);
  std::set<std::string> seen;
  for (const auto& c : cameras) {
    if (c.name.empty() || c.name.find('/') != std::string::npos || c.name.find('\0') != std::string::npos ||
        c.name == "." || c.name == ".." || !seen.insert(c.name).second)
      __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto b = text.find_first_not_of(" \t\r\n");
    if (b != std::string::npos && (text[b] == '[' || text[b] == '{')) {
      const auto res = al::ParseCamerasJson(text, "fuzz.json");
      (void)al::SelectViews(res.cameras, "all");
      CheckNames(res.cameras);
    } else {
      const auto split = text.find('\0');
      const std::string cams = text.substr(0, split);
      const std::string imgs = split == std::string::npos ? std::string() : text.substr(split + 1);
      const auto res = al::ParseColmapText(cams, imgs);
      for (const auto& c : res.cameras) (void)c.Centre();
      CheckNames(res.cameras);
    }
  } catch (const al::Error&) {
  }
  return 0;
}
