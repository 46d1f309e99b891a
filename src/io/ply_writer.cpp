// PLY writer. With a PlySource: the original header (vertex count rewritten) and the kept records
// copied byte for byte, so methods' renderers can read the output (FORMATS.md §2.5). Without one:
// the standard INRIA binary little-endian float layout (RASTERIZER.md §10.1).
#include <algorithm>
#include <bit>
#include <cstring>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/io/ply.hpp"
#include "al/io/kept_records_writer.hpp"
#include "al/io/record_file.hpp"

namespace al {
namespace {

// The source header with `element vertex <kept>`; elements other than vertex (e.g. faces) are
// dropped with their property lines, because their records index vertices that no longer exist
// (and their data is not kept in PlySource).
std::string RewriteHeader(const std::string& header, std::size_t kept) {
  std::string out;
  bool in_other_element = false;
  std::size_t pos = 0;
  while (pos < header.size()) {
    std::size_t nl = header.find('\n', pos);
    if (nl == std::string::npos) nl = header.size() - 1;
    const std::string_view line(header.data() + pos, nl + 1 - pos);
    pos = nl + 1;
    std::string_view body = line;
    while (!body.empty() && (body.back() == '\n' || body.back() == '\r')) body.remove_suffix(1);
    const std::string_view eol = line.substr(body.size());
    if (body.rfind("element ", 0) == 0) {
      const std::string_view rest = body.substr(8);
      const std::string_view name = rest.substr(0, rest.find(' '));
      in_other_element = name != "vertex";
      if (!in_other_element) {
        out += "element vertex " + std::to_string(kept);
        out += eol;
      }
      continue;
    }
    if (in_other_element && body.rfind("property ", 0) == 0) continue;
    out += line;
  }
  return out;
}

void WriteFromSource(std::ostream& os, const std::string& path, const PlySource& src, const std::vector<bool>& keep,
                     std::size_t kept) {
  const std::string header = RewriteHeader(src.header, kept);
  // Binary records of a file-backed scene: assembled in chunks by both cores and written at their
  // offsets (kept_records_writer.hpp: 557 MB of the 3M scene's remaining.ply in ~0.5 s).
  const int out_fd = src.vertex_file && src.format != PlySource::Format::kAscii ? FlushedDescriptor(os) : -1;
  if (out_fd >= 0) {
    WriteKeptRecords(out_fd, path, header, *src.vertex_file, src.record_bytes, keep);
    return;
  }
  os.write(header.data(), static_cast<std::streamsize>(header.size()));
  const std::size_t n = keep.size();
  // Runs of kept records come from memory, else are re-read in bounded chunks.
  std::string chunk;
  auto emit = [&](std::size_t begin, std::size_t end) {
    if (src.vertex_bytes) {
      os.write(src.vertex_bytes->data() + begin, static_cast<std::streamsize>(end - begin));
      return;
    }
    constexpr std::size_t kChunk = std::size_t{8} << 20;
    for (std::size_t at = begin; at < end; at += kChunk) {
      const std::size_t len = std::min(kChunk, end - at);
      chunk.resize(len);
      src.vertex_file->Read(at, len, chunk.data());
      os.write(chunk.data(), static_cast<std::streamsize>(len));
    }
  };
  // Consecutive kept records are written as one run.
  auto span = [&](std::size_t i) -> std::pair<std::size_t, std::size_t> {
    if (src.format == PlySource::Format::kAscii) return {src.ascii_line_offsets[i], src.ascii_line_offsets[i + 1]};
    return {i * src.record_bytes, (i + 1) * src.record_bytes};
  };
  std::size_t i = 0;
  while (i < n) {
    if (!keep[i]) { ++i; continue; }
    std::size_t j = i;
    while (j < n && keep[j]) ++j;
    const std::size_t begin = span(i).first, end = span(j - 1).second;
    emit(begin, end);
    i = j;
  }
}

// Appends in place: GCC 12 falsely warns (-Warray-bounds, bug 105651) on `literal + std::string`
// temporaries once they are inlined, as the precompiled header makes them here.
void AddFloat(std::string& header, std::string_view name, std::optional<std::size_t> index = std::nullopt) {
  header += "property float ";
  header += name;
  if (index) header += std::to_string(*index);
  header += '\n';
}

void WriteInria(std::ostream& os, const Scene& scene, const std::vector<bool>& keep, std::size_t kept) {
  const int degree = scene.sh.cols() >= 3 ? scene.sh_degree : 0;
  const std::size_t coeffs = static_cast<std::size_t>((degree + 1) * (degree + 1));
  const std::size_t rest = 3 * (coeffs - 1);
  const std::size_t dim = static_cast<std::size_t>(scene.features.cols());
  const std::string prefix = scene.feature_prefix.empty() ||
                                     scene.feature_prefix.find_first_of("/\\. ") != std::string::npos
                                 ? std::string("semantic_")  // empty, or an .npy path: not a property name
                                 : scene.feature_prefix;
  std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(kept) + "\n";
  for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"}) AddFloat(header, name);
  for (std::size_t j = 0; j < rest; ++j) AddFloat(header, "f_rest_", j);
  AddFloat(header, "opacity");
  for (int k = 0; k < 3; ++k) AddFloat(header, "scale_", k);
  for (int k = 0; k < 4; ++k) AddFloat(header, "rot_", k);
  for (std::size_t d = 0; d < dim; ++d) AddFloat(header, prefix, d);
  header += "end_header\n";
  os.write(header.data(), static_cast<std::streamsize>(header.size()));

  const std::size_t floats = 17 + rest + dim;
  std::vector<float> record(floats);
  std::string buffer;
  buffer.reserve(1 << 20);
  const bool have_sh = scene.sh.cols() >= static_cast<Eigen::Index>(coeffs * 3) && scene.sh.rows() == scene.means.rows();
  for (std::size_t i = 0; i < scene.size(); ++i) {
    if (!keep.empty() && !keep[i]) continue;
    const Eigen::Index r = static_cast<Eigen::Index>(i);
    std::size_t q = 0;
    for (int c = 0; c < 3; ++c) record[q++] = scene.means(r, c);
    for (int c = 0; c < 3; ++c) record[q++] = 0.0f;
    for (int c = 0; c < 3; ++c) record[q++] = have_sh ? scene.sh(r, c) : 0.0f;
    // Back to the file's channel-major order: f_rest_{ch*(K-1) + k-1} = sh(i, k*3 + ch).
    for (std::size_t ch = 0; ch < 3; ++ch)
      for (std::size_t k = 1; k < coeffs; ++k) record[q++] = have_sh ? scene.sh(r, static_cast<Eigen::Index>(k * 3 + ch)) : 0.0f;
    record[q++] = scene.opacity_logits.size() > r ? scene.opacity_logits(r) : 0.0f;
    for (int c = 0; c < 3; ++c) record[q++] = scene.log_scales.rows() > r ? scene.log_scales(r, c) : 0.0f;
    for (int c = 0; c < 4; ++c) record[q++] = scene.rotations.rows() > r ? scene.rotations(r, c) : (c == 0 ? 1.0f : 0.0f);
    for (std::size_t d = 0; d < dim; ++d) record[q++] = scene.features(r, static_cast<Eigen::Index>(d));
    static_assert(std::endian::native == std::endian::little, "INRIA writer assumes a little-endian host");
    buffer.append(reinterpret_cast<const char*>(record.data()), floats * sizeof(float));
    if (buffer.size() >= (1 << 20)) {
      os.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  }
  os.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

}  // namespace

void WritePly(const std::string& path, const Scene& scene, const std::vector<bool>& keep) {
  const std::size_t n = scene.size();
  if (!keep.empty() && keep.size() != n)
    throw FileError(path, "keep mask has " + std::to_string(keep.size()) + " entries for " + std::to_string(n) + " Gaussians");
  if (scene.features.size() > 0 && static_cast<std::size_t>(scene.features.rows()) != n)
    throw FileError(path, "feature rows do not match the number of Gaussians");
  std::size_t kept = n;
  if (!keep.empty()) kept = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), true));
  const PlySource* src = scene.ply.get();
  if (src && (src->vertex_bytes || src->vertex_file)) {
    const std::size_t record_area = src->vertex_bytes ? src->vertex_bytes->size() : src->vertex_file->size();
    const std::size_t source_n = src->format == PlySource::Format::kAscii
                                     ? (src->ascii_line_offsets.empty() ? 0 : src->ascii_line_offsets.size() - 1)
                                     : (src->record_bytes ? record_area / src->record_bytes : 0);
    if (source_n != n)
      throw FileError(path, "scene has " + std::to_string(n) + " Gaussians but its PLY source has " + std::to_string(source_n));
    const std::vector<bool> all = keep.empty() ? std::vector<bool>(n, true) : std::vector<bool>();
    const std::vector<bool>& mask = keep.empty() ? all : keep;
    WriteFileAtomically(path, [&](std::ostream& os) { WriteFromSource(os, path, *src, mask, kept); });
    return;
  }
  WriteFileAtomically(path, [&](std::ostream& os) { WriteInria(os, scene, keep, kept); });
}

}  // namespace al
