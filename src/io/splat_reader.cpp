// antimatter15 .splat reader (RASTERIZER.md §10.4) and ReadScene by extension.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "al/core/error.hpp"
#include "al/io/ply.hpp"
#include "src/io/mapped_file.hpp"

namespace al {
namespace {
constexpr float kC0 = 0.28209479177387814f;
constexpr std::size_t kRecordBytes = 32;
}  // namespace

Scene ReadSplatFromMemory(const void* data_ptr, std::size_t size, const std::string& path) {
  if (size == 0) throw FileError(path, "empty .splat file");
  if (size % kRecordBytes != 0)
    throw FileError(path, "size " + std::to_string(size) + " is not a multiple of 32 (truncated .splat?)");
  const auto* data = static_cast<const unsigned char*>(data_ptr);
  const std::size_t n = size / kRecordBytes;
  Scene s;
  s.source_path = path;
  s.source_format = "splat";
  s.sh_degree = 0;
  s.means.resize(n, 3);
  s.log_scales.resize(n, 3);
  s.rotations.resize(n, 4);
  s.opacity_logits.resize(n);
  s.sh.resize(n, 3);
  s.has_opacity = s.has_scales = s.has_rotations = s.has_f_dc = true;
  // The 8-bit opacity cannot say 0 or 1 exactly; half a quantisation step keeps the logit finite.
  constexpr float kMinAlpha = 0.5f / 255.0f;
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static) if (n > 65536)
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    const unsigned char* r = data + static_cast<std::size_t>(i) * kRecordBytes;
    float f[6];
    std::memcpy(f, r, sizeof f);
    for (int c = 0; c < 3; ++c) {
      s.means(i, c) = f[c];
      s.log_scales(i, c) = std::log(f[3 + c]);  // scale 0 -> -inf, counted as non-finite
      s.sh(i, c) = (static_cast<float>(r[24 + c]) / 255.0f - 0.5f) / kC0;
    }
    const float alpha = std::clamp(static_cast<float>(r[27]) / 255.0f, kMinAlpha, 1.0f - kMinAlpha);
    s.opacity_logits(i) = std::log(alpha / (1.0f - alpha));
    float q[4], norm2 = 0;
    for (int c = 0; c < 4; ++c) {
      q[c] = (static_cast<float>(r[28 + c]) - 128.0f) / 128.0f;
      norm2 += q[c] * q[c];
    }
    if (norm2 > 0) {
      const float inv = 1.0f / std::sqrt(norm2);
      for (int c = 0; c < 4; ++c) s.rotations(i, c) = q[c] * inv;
    } else {
      s.rotations.row(i) << 1.0f, 0.0f, 0.0f, 0.0f;  // all bytes 128: identity by convention
    }
  }
  return s;
}

Scene ReadSplat(const std::string& path) {
  const io::MappedFile file(path);
  return ReadSplatFromMemory(file.data(), file.size(), path);
}

Scene ReadScene(const std::string& path, const PlyReadOptions& options) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".ply") return ReadPly(path, options);
  if (ext == ".splat") return ReadSplat(path);
  throw FileError(path, "unknown scene format '" + ext + "' (expected .ply or .splat)");
}

}  // namespace al
