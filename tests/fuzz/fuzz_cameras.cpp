// Fuzz target: camera parsers. Input starting with '[' or '{' goes to the JSON parser (INRIA or
// plain list); otherwise it is split at the first NUL byte into cameras.txt and images.txt.
#include <cstdint>
#include <string>

#include "al/core/error.hpp"
#include "al/io/cameras.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto b = text.find_first_not_of(" \t\r\n");
    if (b != std::string::npos && (text[b] == '[' || text[b] == '{')) {
      const auto res = al::ParseCamerasJson(text, "fuzz.json");
      (void)al::SelectViews(res.cameras, "all");
    } else {
      const auto split = text.find('\0');
      const std::string cams = text.substr(0, split);
      const std::string imgs = split == std::string::npos ? std::string() : text.substr(split + 1);
      const auto res = al::ParseColmapText(cams, imgs);
      for (const auto& c : res.cameras) (void)c.Centre();
    }
  } catch (const al::Error&) {
  }
  return 0;
}
