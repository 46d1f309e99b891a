// A 3DGS scene as structure-of-arrays. The row order is the index space of every mask and
// output (the input file's vertex order). Values are raw (pre-activation), as stored in PLY.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace al {

using MatX3f = Eigen::Matrix<float, Eigen::Dynamic, 3>;           // column-major: SoA columns
using MatX4f = Eigen::Matrix<float, Eigen::Dynamic, 4>;
using MatXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic>;
using RowMatXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// How a PLY stored its vertices, kept so the writer can copy kept records byte for byte.
struct PlyProperty {
  std::string name;
  std::string type;        // PLY type name as written in the header ("float", "uchar", ...)
  int size_bytes = 0;      // 1, 2, 4 or 8
  std::size_t offset = 0;  // byte offset inside a binary record (unused for ASCII)
};

class RecordFile;  // al/io/record_file.hpp

struct PlySource {
  enum class Format { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
  std::string path;
  Format format = Format::kBinaryLittleEndian;
  std::string header;                       // full header text up to and including "end_header\n"
  std::vector<PlyProperty> properties;      // vertex properties in file order
  std::size_t record_bytes = 0;             // binary: bytes per vertex record
  std::vector<std::string> extra_elements;  // header lines of elements other than vertex (dropped by the writer)
  // Raw vertex records: binary = N*record_bytes bytes; ASCII = the vertex lines, each ending in '\n'.
  // Binary PLYs read from a file leave their records in the file (vertex_file) instead, so a loaded
  // scene does not hold its file twice; in-memory parses (and ASCII) keep vertex_bytes.
  std::shared_ptr<const std::string> vertex_bytes;
  std::shared_ptr<const RecordFile> vertex_file;
  std::vector<std::uint64_t> ascii_line_offsets;  // ASCII only: N+1 offsets into vertex_bytes
};

struct Scene {
  std::size_t size() const { return static_cast<std::size_t>(means.rows()); }

  MatX3f means;           // x y z
  MatX3f log_scales;      // scale_0..2 (log sigma)
  MatX4f rotations;       // rot_0..3 = quaternion (w, x, y, z), not normalised
  Eigen::VectorXf opacity_logits;
  // SH coefficients, coefficient-major per Gaussian: sh(i, k*3 + ch), k in [0, (deg+1)^2).
  // Column block 0..2 is f_dc; f_rest (channel-major in the file) is reordered on load.
  RowMatXf sh;
  int sh_degree = 0;

  // Optional per-Gaussian features (N x D), row i <-> Gaussian i; empty when none.
  RowMatXf features;
  std::string feature_prefix;  // e.g. "semantic_", or a file path for .npy features

  // Which standard columns the file had (a subset PLY may lack some; matching uses only these).
  bool has_opacity = false, has_scales = false, has_rotations = false, has_f_dc = false;

  // Rows with a non-finite value in a column read but not decoded (PlyReadOptions::sh_rest,
  // rotations = false); empty when every column was decoded. Such rows are excluded like any non-finite one.
  std::vector<std::uint8_t> nonfinite_undecoded;

  std::string source_path;
  std::string source_format;  // "ply" or "splat"
  std::shared_ptr<const PlySource> ply;  // present for PLY input: enables byte-exact writing
};

}  // namespace al
