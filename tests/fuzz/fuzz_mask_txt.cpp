// Fuzz target: the .txt index-list parser of --removed (al::RemovalSetFromIndexText).
#include <cstdint>
#include <string>

#include "al/core/error.hpp"
#include "al/io/masks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // A scene size that small indices hit and large ones exceed.
    const al::RemovalSet r = al::RemovalSetFromIndexText(text, "fuzz.txt", 1000);
    (void)al::MaskToIndices(r.removed);
  } catch (const al::Error&) {
  }
  return 0;
}
