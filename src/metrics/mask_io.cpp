#include "al/metrics/mask_io.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/core/memory_limit.hpp"
#include "al/io/image.hpp"

namespace al::metrics {

namespace {

using json = nlohmann::json;
constexpr std::int64_t kMaxPixels = std::int64_t(1) << 26;  // 67 Mpixel: refuse absurd sizes from hostile JSON

std::string ReadText(const std::string& path) {
  return ReadInputFile(path);
}

json ParseJson(const std::string& text, const std::string& source) {
  json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) throw FileError(source, "invalid JSON");
  return j;
}

std::string NormaliseClass(std::string s) {
  for (auto& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  auto strip = [&] {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    std::size_t b = 0;
    while (b < s.size() && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
    s.erase(0, b);
  };
  strip();
  if (!s.empty() && s.back() == '.') s.pop_back(), strip();
  return s;
}

void CheckSize(std::int64_t h, std::int64_t w, const std::string& source) {
  if (h < 0 || w < 0 || h > std::numeric_limits<int>::max() || w > std::numeric_limits<int>::max() ||
      (h > 0 && w > kMaxPixels / h))
    throw FileError(source, "invalid mask size " + std::to_string(h) + "x" + std::to_string(w));
}

}  // namespace

std::string FileStem(const std::string& path) { return std::filesystem::path(path).stem().string(); }

Gray8 LoadGray8Png(const std::string& path, bool* lossy) {
  const PngData png = ReadPng(path);
  try {
    return ToLuma8(png, lossy);
  } catch (const Error& e) {
    throw FileError(path, e.what());
  }
}

std::vector<std::int64_t> DecodeCocoRleString(const std::string& s, const std::string& source) {
  std::vector<std::int64_t> counts;
  std::size_t p = 0;
  while (p < s.size()) {
    std::int64_t x = 0;
    int k = 0;
    bool more = true;
    while (more) {
      if (p >= s.size()) throw FileError(source, "truncated RLE string");
      const int c = int(static_cast<unsigned char>(s[p])) - 48;
      if (c < 0 || c > 63) throw FileError(source, "invalid character in RLE string");
      if (k >= 12) throw FileError(source, "RLE run length overflows");
      x |= std::int64_t(c & 0x1f) << (5 * k);
      more = (c & 0x20) != 0;
      ++p;
      ++k;
      if (!more && (c & 0x10)) x |= ~((std::int64_t(1) << (5 * k)) - 1);  // sign-extend
    }
    if (counts.size() > 2) {
      const std::int64_t prev = counts[counts.size() - 2];
      if ((x > 0 && prev > std::numeric_limits<std::int64_t>::max() - x) ||
          (x < 0 && prev < std::numeric_limits<std::int64_t>::min() - x))
        throw FileError(source, "RLE run length overflows");
      x += prev;
    }
    counts.push_back(x);
  }
  return counts;
}

Mask MaskFromRleCounts(const std::vector<std::int64_t>& counts, int height, int width, const std::string& source) {
  CheckSize(height, width, source);
  const std::int64_t total = std::int64_t(height) * width;
  std::int64_t sum = 0;
  for (std::int64_t c : counts) {
    if (c < 0) throw FileError(source, "negative RLE run length");
    if (c > total - sum) throw FileError(source, "RLE runs exceed the mask size");
    sum += c;
  }
  if (sum != total)
    throw FileError(source, "RLE runs cover " + std::to_string(sum) + " pixels, mask has " + std::to_string(total));
  Mask m = EmptyMask(width, height);
  std::int64_t pos = 0;  // column-major position
  for (std::size_t r = 0; r < counts.size(); ++r) {
    if (r % 2 == 1)
      for (std::int64_t q = pos; q < pos + counts[r]; ++q) {
        const std::int64_t x = q / height, y = q % height;
        m.bits[std::size_t(y) * width + std::size_t(x)] = 1;
      }
    pos += counts[r];
  }
  return m;
}

Mask MaskFromCocoRle(const json& rle, const std::string& source) {
  if (!rle.is_object() || !rle.contains("size") || !rle.contains("counts"))
    throw FileError(source, "RLE needs \"size\" and \"counts\"");
  const json& size = rle["size"];
  if (!size.is_array() || size.size() != 2 || !size[0].is_number_integer() || !size[1].is_number_integer())
    throw FileError(source, "RLE \"size\" must be [height, width]");
  const std::int64_t h = size[0].get<std::int64_t>(), w = size[1].get<std::int64_t>();
  CheckSize(h, w, source);
  const json& c = rle["counts"];
  std::vector<std::int64_t> counts;
  if (c.is_string()) {
    counts = DecodeCocoRleString(c.get<std::string>(), source);
  } else if (c.is_array()) {
    for (const auto& v : c) {
      if (!v.is_number_integer()) throw FileError(source, "RLE \"counts\" list must hold integers");
      counts.push_back(v.get<std::int64_t>());
    }
  } else {
    throw FileError(source, "RLE \"counts\" must be a string or a list");
  }
  return MaskFromRleCounts(counts, int(h), int(w), source);
}

Mask MaskFromSegmentation(const json& value, const std::string& source) {
  if (value.is_object()) return MaskFromCocoRle(value, source);
  if (!value.is_array()) throw FileError(source, "segmentation must be a 2-D array or a COCO RLE object");
  const std::int64_t h = std::int64_t(value.size());
  const std::int64_t w = h > 0 && value[0].is_array() ? std::int64_t(value[0].size()) : 0;
  CheckSize(h, w, source);
  Mask m = EmptyMask(int(w), int(h));
  for (std::int64_t y = 0; y < h; ++y) {
    const json& row = value[std::size_t(y)];
    if (!row.is_array() || std::int64_t(row.size()) != w) throw FileError(source, "ragged segmentation array");
    for (std::int64_t x = 0; x < w; ++x) {
      const json& v = row[std::size_t(x)];
      bool on;
      if (v.is_boolean()) on = v.get<bool>();
      else if (v.is_number()) on = v.get<double>() != 0.0;
      else throw FileError(source, "segmentation values must be booleans or numbers");
      m.bits[std::size_t(y) * std::size_t(w) + std::size_t(x)] = on;
    }
  }
  return m;
}

std::vector<Mask> ParseSamList(const json& list, const std::string& source) {
  if (!list.is_array()) throw FileError(source, "SAM segment list must be a JSON array");
  std::vector<Mask> masks;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const json& seg = list[i];
    if (!seg.is_object()) continue;
    const char* key = seg.contains("segmentation") ? "segmentation" : seg.contains("mask") ? "mask" : nullptr;
    if (!key) continue;  // released behaviour: objects without a mask are ignored
    masks.push_back(MaskFromSegmentation(seg[key], source + ": segment " + std::to_string(i)));
  }
  return masks;
}

namespace {

// Pixels a segment declares (a COCO RLE's "size" can ask for 67 Mpixel in a few bytes of JSON).
double DeclaredPixels(const json& seg) {
  if (!seg.is_object()) return 0;
  const char* key = seg.contains("segmentation") ? "segmentation" : seg.contains("mask") ? "mask" : nullptr;
  if (!key) return 0;
  const json& v = seg[key];
  if (v.is_array()) return double(v.size()) * (!v.empty() && v[0].is_array() ? double(v[0].size()) : 0.0);
  if (!v.is_object() || !v.contains("size")) return 0;
  const json& size = v["size"];
  if (!size.is_array() || size.size() != 2 || !size[0].is_number_integer() || !size[1].is_number_integer()) return 0;
  return std::max(0.0, size[0].get<double>()) * std::max(0.0, size[1].get<double>());
}

// Every list of a SAM file is decoded at once: refuse a file whose masks exceed --max-memory
// before any is allocated.
void CheckSamMemory(const json& j, const std::string& source) {
  double pixels = 0;
  std::size_t segments = 0;
  const auto add_list = [&](const json& list) {
    if (!list.is_array()) return;
    for (const auto& seg : list) pixels += DeclaredPixels(seg), ++segments;
  };
  if (j.is_array()) add_list(j);
  if (j.is_object())
    for (const auto& [name, list] : j.items()) add_list(list);
  CheckMemoryEstimate(source + ": decoding " + std::to_string(segments) + " SAM masks", pixels * sizeof(std::uint8_t));
}

}  // namespace

std::map<std::string, std::vector<Mask>> ParseSamJsonText(const std::string& text, const std::string& source) {
  const json j = ParseJson(text, source);
  CheckSamMemory(j, source);
  std::map<std::string, std::vector<Mask>> out;
  if (j.is_array()) {
    out[""] = ParseSamList(j, source);
  } else if (j.is_object()) {
    for (const auto& [name, list] : j.items()) out[FileStem(name)] = ParseSamList(list, source + ": " + name);
  } else {
    throw FileError(source, "expected a list of SAM segments or {image_name: [segments]}");
  }
  return out;
}

std::map<std::string, std::vector<Mask>> LoadSamJson(const std::string& path) {
  return ParseSamJsonText(ReadText(path), path);
}

GroundedSamMask ParseGroundedSamText(const std::string& text, const std::string& class_name,
                                     const std::string& source) {
  const json j = ParseJson(text, source);
  if (!j.is_object() || !j.contains("annotations") || !j["annotations"].is_array())
    throw FileError(source, "GroundedSAM JSON needs an \"annotations\" list");
  GroundedSamMask r;
  std::int64_t w = 0, h = 0;
  if (j.contains("img_width") && j.contains("img_height")) {
    if (!j["img_width"].is_number_integer() || !j["img_height"].is_number_integer())
      throw FileError(source, "img_width/img_height must be integers");
    w = j["img_width"].get<std::int64_t>();
    h = j["img_height"].get<std::int64_t>();
    CheckSize(h, w, source);
  }
  const std::string wanted = NormaliseClass(class_name);
  std::vector<Mask> picked;
  for (const json& ann : j["annotations"]) {
    ++r.annotations;
    if (!ann.is_object() || !ann.contains("segmentation")) throw FileError(source, "annotation without segmentation");
    if (!wanted.empty()) {
      if (!ann.contains("class_name") || !ann["class_name"].is_string()) continue;
      if (NormaliseClass(ann["class_name"].get<std::string>()) != wanted) continue;
    }
    picked.push_back(MaskFromSegmentation(ann["segmentation"], source));
    if (w == 0 && h == 0) w = picked.back().width, h = picked.back().height;
  }
  r.mask = {int(w), int(h), std::vector<std::uint8_t>(std::size_t(w) * std::size_t(h), 0)};
  for (const Mask& m : picked) {
    if (m.width != w || m.height != h) throw FileError(source, "instance mask size differs from the image size");
    for (std::size_t i = 0; i < m.bits.size(); ++i)
      if (m.bits[i]) r.mask.pixels[i] = 255;
  }
  r.instances = picked.size();
  return r;
}

GroundedSamMask LoadGroundedSamJson(const std::string& path, const std::string& class_name) {
  return ParseGroundedSamText(ReadText(path), class_name, path);
}

}  // namespace al::metrics
