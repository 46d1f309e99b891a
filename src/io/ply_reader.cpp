// PLY reader: header parse, column plan (name -> Scene column), one pass over the vertex records.
// The fast path (every property float32 in host byte order) is the plyfile/INRIA layout; every
// other layout goes through a per-property converting loop. RASTERIZER.md §10.1, FORMATS.md §2.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string_view>

#include "al/core/error.hpp"
#include "al/core/memory_limit.hpp"
#include "al/io/ply.hpp"
#include "al/io/record_file.hpp"
#include "src/io/mapped_file.hpp"

namespace al {
namespace {

enum class ScalarType { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

std::optional<ScalarType> ParseType(std::string_view t) {
  if (t == "char" || t == "int8") return ScalarType::kInt8;
  if (t == "uchar" || t == "uint8") return ScalarType::kUInt8;
  if (t == "short" || t == "int16") return ScalarType::kInt16;
  if (t == "ushort" || t == "uint16") return ScalarType::kUInt16;
  if (t == "int" || t == "int32") return ScalarType::kInt32;
  if (t == "uint" || t == "uint32") return ScalarType::kUInt32;
  if (t == "float" || t == "float32") return ScalarType::kFloat32;
  if (t == "double" || t == "float64") return ScalarType::kFloat64;
  return std::nullopt;
}

int TypeSize(ScalarType t) {
  switch (t) {
    case ScalarType::kInt8: case ScalarType::kUInt8: return 1;
    case ScalarType::kInt16: case ScalarType::kUInt16: return 2;
    case ScalarType::kInt32: case ScalarType::kUInt32: case ScalarType::kFloat32: return 4;
    case ScalarType::kFloat64: return 8;
  }
  return 0;
}

struct HeaderProperty {
  std::string name, type_name;
  ScalarType type = ScalarType::kFloat32;
  bool is_list = false;
  ScalarType count_type = ScalarType::kUInt8;
};

struct HeaderElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<HeaderProperty> properties;
};

struct Header {
  PlySource::Format format = PlySource::Format::kBinaryLittleEndian;
  std::vector<HeaderElement> elements;
  std::size_t length = 0;  // bytes up to and including the end_header line terminator
};

std::vector<std::string_view> Tokens(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

bool ParseUInt(std::string_view s, std::uint64_t& value) {
  if (s.empty()) return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), value);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

Header ParseHeader(const char* data, std::size_t size, const std::string& path) {
  // A header longer than this is not a PLY we want to guess about (keeps fuzzing cheap).
  constexpr std::size_t kMaxHeader = 1 << 20;
  Header h;
  std::size_t pos = 0;
  int line_no = 0;
  bool saw_format = false, saw_end = false;
  while (pos < size && !saw_end) {
    if (pos > kMaxHeader) throw FileError(path, "header longer than 1 MiB (no end_header)");
    const char* nl = static_cast<const char*>(std::memchr(data + pos, '\n', size - pos));
    if (!nl) throw FileError(path, "header not terminated by end_header");
    std::string_view line(data + pos, static_cast<std::size_t>(nl - (data + pos)));
    pos = static_cast<std::size_t>(nl - data) + 1;
    ++line_no;
    const auto tok = Tokens(line);
    const std::string where = " (header line " + std::to_string(line_no) + ")";
    if (line_no == 1) {
      if (tok.size() != 1 || tok[0] != "ply") throw FileError(path, "missing PLY magic 'ply'");
      continue;
    }
    if (tok.empty()) continue;
    if (tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "format") {
      if (tok.size() != 3) throw FileError(path, "bad format line" + where);
      if (tok[1] == "ascii") h.format = PlySource::Format::kAscii;
      else if (tok[1] == "binary_little_endian") h.format = PlySource::Format::kBinaryLittleEndian;
      else if (tok[1] == "binary_big_endian") h.format = PlySource::Format::kBinaryBigEndian;
      else throw FileError(path, "unknown format '" + std::string(tok[1]) + "'" + where);
      if (tok[2] != "1.0") throw FileError(path, "unsupported PLY version '" + std::string(tok[2]) + "'" + where);
      saw_format = true;
    } else if (tok[0] == "element") {
      HeaderElement e;
      if (tok.size() != 3 || !ParseUInt(tok[2], e.count))
        throw FileError(path, "bad element line" + where);
      e.name = std::string(tok[1]);
      h.elements.push_back(std::move(e));
    } else if (tok[0] == "property") {
      if (h.elements.empty()) throw FileError(path, "property before any element" + where);
      HeaderProperty p;
      if (tok.size() == 5 && tok[1] == "list") {
        const auto ct = ParseType(tok[2]);
        const auto vt = ParseType(tok[3]);
        if (!ct || !vt) throw FileError(path, "unknown list property type" + where);
        p.is_list = true;
        p.count_type = *ct;
        p.type = *vt;
        p.type_name = std::string(tok[3]);
        p.name = std::string(tok[4]);
      } else if (tok.size() == 3) {
        const auto t = ParseType(tok[1]);
        if (!t) throw FileError(path, "unknown property type '" + std::string(tok[1]) + "'" + where);
        p.type = *t;
        p.type_name = std::string(tok[1]);
        p.name = std::string(tok[2]);
      } else {
        throw FileError(path, "bad property line" + where);
      }
      h.elements.back().properties.push_back(std::move(p));
    } else if (tok[0] == "end_header") {
      saw_end = true;
    } else {
      throw FileError(path, "unexpected header keyword '" + std::string(tok[0]) + "'" + where);
    }
  }
  if (!saw_end) throw FileError(path, "header not terminated by end_header");
  if (!saw_format) throw FileError(path, "missing format line");
  h.length = pos;
  return h;
}

// Where one file property goes: base[i * stride] for Gaussian i.
struct Target {
  std::size_t property = 0;
  float* base = nullptr;          // nullptr: the value is only checked (non-finite -> flag[i] = 1)
  std::size_t stride = 0;
  std::uint8_t* flag = nullptr;
};

// Parses "<prefix><decimal>" and returns the integer, or nullopt.
std::optional<std::uint64_t> Suffix(const std::string& name, std::string_view prefix) {
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  std::string_view rest(name);
  rest.remove_prefix(prefix.size());
  for (char c : rest)
    if (c < '0' || c > '9') return std::nullopt;
  std::uint64_t v = 0;
  if (!ParseUInt(rest, v)) return std::nullopt;
  return v;
}

// Properties "<prefix><k>" with k exactly 0..D-1: returns property indices ordered by k.
std::vector<std::size_t> IndexedColumns(const std::vector<HeaderProperty>& props, std::string_view prefix,
                                        const std::string& path) {
  std::map<std::uint64_t, std::size_t> by_k;
  for (std::size_t p = 0; p < props.size(); ++p) {
    const auto k = Suffix(props[p].name, prefix);
    if (!k) continue;
    if (!by_k.emplace(*k, p).second)
      throw FileError(path, "duplicate property index " + std::string(prefix) + std::to_string(*k));
  }
  std::vector<std::size_t> out;
  std::uint64_t expect = 0;
  for (const auto& [k, p] : by_k) {
    if (k != expect)
      throw FileError(path, "gap in " + std::string(prefix) + "* properties: " + std::string(prefix) +
                                std::to_string(expect) + " missing");
    out.push_back(p);
    ++expect;
  }
  return out;
}

// "auto" = the standard prefixes (FORMATS.md §2.2); "none"/"" = nothing; "a,b,auto" = in that order.
std::vector<std::string> FeaturePrefixPreference(const std::string& spec) {
  std::vector<std::string> out;
  if (spec.empty() || spec == "none") return out;
  std::size_t start = 0;
  while (start <= spec.size()) {
    const std::size_t comma = std::min(spec.find(',', start), spec.size());
    const std::string item = spec.substr(start, comma - start);
    if (item == "auto")
      for (const char* p : {"semantic_", "obj_dc_", "f_semantic_", "feat_"}) out.emplace_back(p);
    else if (!item.empty())
      out.push_back(item);
    start = comma + 1;
  }
  return out;
}

template <typename T>
T LoadSwapped(const unsigned char* p, bool swap) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if (swap) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof(T));
  }
  return v;
}

float LoadAsFloat(const unsigned char* p, ScalarType t, bool swap) {
  switch (t) {
    case ScalarType::kInt8: return static_cast<float>(static_cast<std::int8_t>(p[0]));
    case ScalarType::kUInt8: return static_cast<float>(p[0]);
    case ScalarType::kInt16: return static_cast<float>(LoadSwapped<std::int16_t>(p, swap));
    case ScalarType::kUInt16: return static_cast<float>(LoadSwapped<std::uint16_t>(p, swap));
    case ScalarType::kInt32: return static_cast<float>(LoadSwapped<std::int32_t>(p, swap));
    case ScalarType::kUInt32: return static_cast<float>(LoadSwapped<std::uint32_t>(p, swap));
    case ScalarType::kFloat32: return LoadSwapped<float>(p, swap);
    case ScalarType::kFloat64: return static_cast<float>(LoadSwapped<double>(p, swap));
  }
  return 0.0f;
}

// Bytes of one record of a non-vertex element, or nullopt when it has list properties.
std::optional<std::uint64_t> FixedRecordBytes(const HeaderElement& e) {
  std::uint64_t bytes = 0;
  for (const auto& p : e.properties) {
    if (p.is_list) return std::nullopt;
    bytes += static_cast<std::uint64_t>(TypeSize(p.type));
  }
  return bytes;
}

// Property name -> index; list properties and repeated names are errors.
using PropertyIndex = std::map<std::string, std::size_t>;
PropertyIndex IndexProperties(const std::vector<HeaderProperty>& props, const std::string& path) {
  PropertyIndex by_name;
  for (std::size_t p = 0; p < props.size(); ++p) {
    if (props[p].is_list) throw FileError(path, "list property '" + props[p].name + "' in element vertex");
    if (!by_name.emplace(props[p].name, p).second) throw FileError(path, "duplicate property '" + props[p].name + "'");
  }
  return by_name;
}

std::optional<std::size_t> FindProperty(const PropertyIndex& by_name, const std::string& name) {
  const auto it = by_name.find(name);
  if (it == by_name.end()) return std::nullopt;
  return it->second;
}

// All-or-nothing groups: true when every member is present, an error when only some are.
bool HasGroup(const PropertyIndex& by_name, const std::vector<std::string>& names, const char* what,
              const std::string& path) {
  std::size_t found = 0;
  for (const auto& nm : names) found += FindProperty(by_name, nm) ? 1 : 0;
  if (found != 0 && found != names.size())
    for (const auto& nm : names)
      if (!FindProperty(by_name, nm)) throw FileError(path, std::string("incomplete ") + what + ": missing property '" + nm + "'");
  return found == names.size();
}

// The has_* flags of the scene, and the columns the options require.
void DetectColumnGroups(const PropertyIndex& by_name, const PlyReadOptions& options, const std::string& path,
                        Scene& scene) {
  if (!HasGroup(by_name, {"x", "y", "z"}, "position", path)) throw FileError(path, "missing required property 'x'/'y'/'z'");
  scene.has_scales = HasGroup(by_name, {"scale_0", "scale_1", "scale_2"}, "scales", path);
  scene.has_rotations = HasGroup(by_name, {"rot_0", "rot_1", "rot_2", "rot_3"}, "rotation", path);
  scene.has_f_dc = HasGroup(by_name, {"f_dc_0", "f_dc_1", "f_dc_2"}, "f_dc", path);
  scene.has_opacity = FindProperty(by_name, "opacity").has_value();
  if (options.require_scales && !scene.has_scales) throw FileError(path, "missing required property 'scale_0'");
  if (!options.require_render_columns) return;
  if (!scene.has_opacity) throw FileError(path, "missing required property 'opacity'");
  if (!scene.has_rotations) throw FileError(path, "missing required property 'rot_0'");
  if (!scene.has_f_dc) throw FileError(path, "missing required property 'f_dc_0'");
}

int ShDegreeOf(std::size_t rest_columns, const std::string& path) {
  switch (rest_columns) {
    case 0: return 0;
    case 9: return 1;
    case 24: return 2;
    case 45: return 3;
    default:
      throw FileError(path, "f_rest_* count " + std::to_string(rest_columns) + " is not 0, 9, 24 or 45");
  }
}

// The feature columns the options ask for. feature_prefix: one explicit prefix (strict), or a
// preference list "a,b,..." in which "auto" stands for the standard prefixes; the first present
// wins, none present = no features.
std::vector<std::size_t> FeatureColumns(const std::vector<HeaderProperty>& props, const PlyReadOptions& options,
                                        const std::string& path, Scene& scene) {
  std::vector<std::size_t> feature_cols;
  const std::vector<std::string> wanted = FeaturePrefixPreference(options.feature_prefix);
  for (const std::string& prefix : wanted) {
    feature_cols = IndexedColumns(props, prefix, path);
    if (!feature_cols.empty()) {
      scene.feature_prefix = prefix;
      break;
    }
  }
  if (feature_cols.empty() && wanted.size() == 1 && options.feature_prefix != "auto")
    throw FileError(path, "no feature properties with prefix '" + options.feature_prefix + "'");
  return feature_cols;
}

// Columns the file lacks keep neutral values (the has_* flags say which are real). The ones it
// has are left uninitialised: the decode writes every row of them, in parallel, so their pages are
// touched once there instead of being zeroed on one thread first (a third of the load at 3M).
void AllocateColumns(std::size_t n, std::size_t coeffs, std::size_t features, Scene& scene) {
  const auto rows = static_cast<Eigen::Index>(n);
  scene.means.resize(rows, 3);
  scene.log_scales.resize(rows, 3);
  if (!scene.has_scales) scene.log_scales.setZero();
  scene.rotations.resize(rows, 4);
  if (!scene.has_rotations) {
    scene.rotations.setZero();
    scene.rotations.col(0).setOnes();
  }
  scene.opacity_logits.resize(rows);
  if (!scene.has_opacity) scene.opacity_logits.setZero();
  scene.sh.resize(rows, static_cast<Eigen::Index>(coeffs * 3));  // f_rest: all or none (ShDegreeOf)
  if (!scene.has_f_dc) scene.sh.leftCols(3).setZero();
  if (features > 0) scene.features.resize(rows, static_cast<Eigen::Index>(features));
}

// Builds the column plan and sizes the scene's matrices.
std::vector<Target> PlanColumns(const HeaderElement& vertex, const PlyReadOptions& options,
                                const std::string& path, Scene& scene) {
  const auto& props = vertex.properties;
  const PropertyIndex by_name = IndexProperties(props, path);
  DetectColumnGroups(by_name, options, path, scene);
  const auto rest = IndexedColumns(props, "f_rest_", path);
  scene.sh_degree = ShDegreeOf(rest.size(), path);
  const bool check_rest_only = !options.sh_rest && !rest.empty();
  const bool check_rotations_only = !options.rotations && scene.has_rotations;
  if (check_rest_only) scene.sh_degree = 0;  // what the scene holds: f_dc
  const std::size_t coeffs = static_cast<std::size_t>((scene.sh_degree + 1) * (scene.sh_degree + 1));
  const std::vector<std::size_t> feature_cols = FeatureColumns(props, options, path, scene);
  // Without feature columns the colour fallback reads f_dc: decoded then whatever the options say.
  const bool check_f_dc_only = !options.f_dc && !options.sh_rest && scene.has_f_dc && !feature_cols.empty();
  if (check_rest_only || check_rotations_only || check_f_dc_only)
    scene.nonfinite_undecoded.assign(static_cast<std::size_t>(vertex.count), 0);
  AllocateColumns(static_cast<std::size_t>(vertex.count), coeffs, feature_cols.size(), scene);
  if (check_rotations_only) scene.rotations.resize(0, 4);
  if (check_f_dc_only) scene.sh.resize(0, 3);

  std::vector<Target> plan;
  if (vertex.count == 0) return plan;  // empty matrices have no data pointer to offset from
  auto col_major = [&](const std::string& name, float* column) {
    if (const auto p = FindProperty(by_name, name)) plan.push_back({*p, column, 1});
  };
  for (int c = 0; c < 3; ++c) {
    col_major(std::string(1, "xyz"[c]), scene.means.col(c).data());
    col_major("scale_" + std::to_string(c), scene.log_scales.col(c).data());
  }
  for (int c = 0; c < 4; ++c)
    if (check_rotations_only) plan.push_back({*FindProperty(by_name, "rot_" + std::to_string(c)), nullptr, 0, scene.nonfinite_undecoded.data()});
    else col_major("rot_" + std::to_string(c), scene.rotations.col(c).data());
  col_major("opacity", scene.opacity_logits.data());
  const std::size_t sh_cols = coeffs * 3;
  for (int c = 0; c < 3; ++c)
    if (const auto p = FindProperty(by_name, "f_dc_" + std::to_string(c)))
      plan.push_back(check_f_dc_only ? Target{*p, nullptr, 0, scene.nonfinite_undecoded.data()}
                                     : Target{*p, scene.sh.data() + c, sh_cols});
  if (check_rest_only)
    for (std::size_t j : rest) plan.push_back({j, nullptr, 0, scene.nonfinite_undecoded.data()});
  // f_rest_j is channel-major in the file: j = ch*(K-1) + (k-1)  ->  sh(i, k*3 + ch).
  for (std::size_t j = 0; j < rest.size() && !check_rest_only; ++j) {
    const std::size_t ch = j / (coeffs - 1), k = j % (coeffs - 1) + 1;
    plan.push_back({rest[j], scene.sh.data() + k * 3 + ch, sh_cols});
  }
  for (std::size_t d = 0; d < feature_cols.size(); ++d)
    plan.push_back({feature_cols[d], scene.features.data() + d, feature_cols.size()});
  // Property order = memory order of a record: friendlier to the cache than column order.
  std::stable_sort(plan.begin(), plan.end(), [](const Target& a, const Target& b) { return a.property < b.property; });
  return plan;
}

// Decodes n records and copies their raw bytes to `copy` (the PlySource) in the same pass: each
// block is copied first and decoded from the copy while it is still in cache.
void DecodeBinary(const unsigned char* records, std::size_t n, std::size_t record_bytes,
                  const std::vector<ScalarType>& types, const std::vector<std::size_t>& offsets,
                  const std::vector<Target>& plan, bool file_little_endian, unsigned char* copy) {
  const bool swap = file_little_endian != (std::endian::native == std::endian::little);
  const bool all_float = !swap && std::all_of(plan.begin(), plan.end(), [&](const Target& t) {
    return types[t.property] == ScalarType::kFloat32;
  });
  constexpr std::size_t kBlock = 256;  // records per block: ~64 KB for SH3, stays in L2
  const std::ptrdiff_t blocks = static_cast<std::ptrdiff_t>((n + kBlock - 1) / kBlock);
  if (all_float) {
    // Fast path (INRIA/plyfile layout): float32 in host order, plain loads.
    struct Flat { std::size_t offset; float* base; std::size_t stride; };
    std::vector<Flat> flat;
    std::vector<std::size_t> checked;  // offsets of the values only checked for finiteness
    for (const auto& t : plan)
      if (t.base) flat.push_back({offsets[t.property], t.base, t.stride});
      else checked.push_back(offsets[t.property]);
    std::uint8_t* flag = nullptr;
    for (const auto& t : plan)
      if (!t.base) flag = t.flag;
    const Flat* f = flat.data();
    const std::size_t m = flat.size();
#pragma omp parallel for schedule(static) if (n > 32768)
    for (std::ptrdiff_t b = 0; b < blocks; ++b) {
      const std::size_t begin = static_cast<std::size_t>(b) * kBlock, end = std::min(n, begin + kBlock);
      if (copy) std::memcpy(copy + begin * record_bytes, records + begin * record_bytes, (end - begin) * record_bytes);
      for (std::size_t i = begin; i < end; ++i) {
        const unsigned char* rec = (copy ? copy : records) + i * record_bytes;
        for (std::size_t q = 0; q < m; ++q) {
          float v;
          std::memcpy(&v, rec + f[q].offset, sizeof(float));
          f[q].base[i * f[q].stride] = v;
        }
        for (const std::size_t offset : checked) {
          float v;
          std::memcpy(&v, rec + offset, sizeof(float));
          if (!std::isfinite(v)) flag[i] = 1;
        }
      }
    }
    return;
  }
#pragma omp parallel for schedule(static) if (n > 32768)
  for (std::ptrdiff_t b = 0; b < blocks; ++b) {
    const std::size_t begin = static_cast<std::size_t>(b) * kBlock, end = std::min(n, begin + kBlock);
    if (copy) std::memcpy(copy + begin * record_bytes, records + begin * record_bytes, (end - begin) * record_bytes);
    for (std::size_t i = begin; i < end; ++i) {
      const unsigned char* rec = (copy ? copy : records) + i * record_bytes;
      for (const auto& t : plan) {
        const float v = LoadAsFloat(rec + offsets[t.property], types[t.property], swap);
        if (t.base) t.base[i * t.stride] = v;
        else if (!std::isfinite(v)) t.flag[i] = 1;
      }
    }
  }
}

// Next non-blank line starting at pos; returns false at the end of the buffer.
bool NextLine(const char* data, std::size_t size, std::size_t& pos, std::string_view& line) {
  while (pos < size) {
    const char* nl = static_cast<const char*>(std::memchr(data + pos, '\n', size - pos));
    const std::size_t end = nl ? static_cast<std::size_t>(nl - data) : size;
    line = std::string_view(data + pos, end - pos);
    pos = nl ? end + 1 : size;
    if (!Tokens(line).empty()) return true;
  }
  return false;
}

bool ParseAsciiValue(std::string_view tok, float& out) {
  double v = 0;
  const char* b = tok.data();
  const char* e = tok.data() + tok.size();
  if (b != e && *b == '+') ++b;  // from_chars rejects a leading '+', PLY writers may emit it
  const auto r = std::from_chars(b, e, v);
  if (r.ec == std::errc::result_out_of_range) {
    // Overflow / underflow: keep the sign, saturate like a float cast would.
    out = (b != e && *b == '-') ? -std::numeric_limits<float>::infinity() : std::numeric_limits<float>::infinity();
    return r.ptr == e;
  }
  if (r.ec != std::errc() || r.ptr != e) return false;
  out = static_cast<float>(v);
  return true;
}

}  // namespace

namespace {

std::size_t VertexElementIndex(const Header& h, const std::string& path) {
  for (std::size_t e = 0; e < h.elements.size(); ++e)
    if (h.elements[e].name == "vertex") return e;
  throw FileError(path, "no 'element vertex' in header");
}

// Types and byte offsets of the vertex properties within a record; the source keeps them to write
// the records back unchanged.
struct RecordLayout {
  std::vector<ScalarType> types;
  std::vector<std::size_t> offsets;
  std::size_t bytes = 0;
};
RecordLayout DescribeRecords(const HeaderElement& vertex, PlySource& src) {
  RecordLayout layout;
  for (const auto& p : vertex.properties) {
    layout.types.push_back(p.type);
    layout.offsets.push_back(layout.bytes);
    src.properties.push_back({p.name, p.type_name, TypeSize(p.type), layout.bytes});
    layout.bytes += static_cast<std::size_t>(TypeSize(p.type));
  }
  return layout;
}

// Bytes of the fixed-size elements before the vertex element (they are skipped).
std::uint64_t BytesBeforeVertices(const Header& h, std::size_t vertex_index, std::size_t body, const std::string& path) {
  std::uint64_t skip = 0;
  for (std::size_t e = 0; e < vertex_index; ++e) {
    const auto rb = FixedRecordBytes(h.elements[e]);
    if (!rb) throw FileError(path, "cannot skip element '" + h.elements[e].name + "' (list properties) before element vertex");
    if (*rb != 0 && h.elements[e].count > body / *rb) throw FileError(path, "truncated data in element '" + h.elements[e].name + "'");
    skip += *rb * h.elements[e].count;
    if (skip > body) throw FileError(path, "truncated data in element '" + h.elements[e].name + "'");
  }
  return skip;
}

void ReadBinaryVertices(const char* data, std::size_t size, const Header& h, std::size_t vertex_index,
                        const RecordLayout& layout, const std::vector<Target>& plan, const std::string& path,
                        bool file_backed, PlySource& src) {
  const std::size_t n = static_cast<std::size_t>(h.elements[vertex_index].count), body = size - h.length;
  src.record_bytes = layout.bytes;
  const std::uint64_t skip = BytesBeforeVertices(h, vertex_index, body, path);
  if (n > 0 && (body - skip) / layout.bytes < n)
    throw FileError(path, "truncated data: " + std::to_string(n) + " vertices of " + std::to_string(layout.bytes) +
                              " bytes need " + std::to_string(n * layout.bytes) + " bytes, file has " +
                              std::to_string(body - skip) + " after the header");
  const auto* records = reinterpret_cast<const unsigned char*>(data + h.length + skip);
  const bool little = h.format == PlySource::Format::kBinaryLittleEndian;
  if (file_backed) {
    src.vertex_file = std::make_shared<const RecordFile>(path, h.length + skip, n * layout.bytes);
    DecodeBinary(records, n, layout.bytes, layout.types, layout.offsets, plan, little, nullptr);
    return;
  }
  auto raw = std::make_shared<std::string>(n * layout.bytes, '\0');
  DecodeBinary(records, n, layout.bytes, layout.types, layout.offsets, plan, little,
               reinterpret_cast<unsigned char*>(raw->data()));
  src.vertex_bytes = std::move(raw);
}

void ReadAsciiVertices(const char* data, std::size_t size, const Header& h, std::size_t vertex_index,
                       const std::vector<Target>& plan, const std::string& path, PlySource& src) {
  const HeaderElement& vertex = h.elements[vertex_index];
  const std::size_t n = static_cast<std::size_t>(vertex.count);
  std::size_t pos = h.length;
  std::string_view line;
  for (std::size_t e = 0; e < vertex_index; ++e)
    for (std::uint64_t r = 0; r < h.elements[e].count; ++r)
      if (!NextLine(data, size, pos, line)) throw FileError(path, "truncated data in element '" + h.elements[e].name + "'");
  // Which plan entries read property p (a property may feed several columns).
  std::vector<std::vector<const Target*>> by_property(vertex.properties.size());
  for (const auto& t : plan) by_property[t.property].push_back(&t);
  auto bytes = std::make_shared<std::string>();
  src.ascii_line_offsets.reserve(n + 1);
  for (std::size_t i = 0; i < n; ++i) {
    if (!NextLine(data, size, pos, line))
      throw FileError(path, "truncated data: " + std::to_string(n) + " vertices declared, " + std::to_string(i) + " lines found");
    const auto tok = Tokens(line);
    if (tok.size() != vertex.properties.size())
      throw FileError(path, "vertex " + std::to_string(i) + " has " + std::to_string(tok.size()) + " values, expected " +
                                std::to_string(vertex.properties.size()));
    for (std::size_t p = 0; p < tok.size(); ++p) {
      float v = 0;
      if (!ParseAsciiValue(tok[p], v))
        throw FileError(path, "non-numeric value '" + std::string(tok[p].substr(0, 32)) + "' for property '" +
                                  vertex.properties[p].name + "' of vertex " + std::to_string(i));
      for (const Target* t : by_property[p])
        if (t->base) t->base[i * t->stride] = v;
        else if (!std::isfinite(v)) t->flag[i] = 1;
    }
    src.ascii_line_offsets.push_back(bytes->size());
    bytes->append(line);
    bytes->push_back('\n');
  }
  src.ascii_line_offsets.push_back(bytes->size());
  src.vertex_bytes = std::move(bytes);
}

// file_backed: the bytes are the whole file at `path`; binary vertex records are then re-read from
// the file by the writer instead of being copied (see PlySource::vertex_file).
Scene ReadPlyImpl(const void* data_ptr, std::size_t size, const std::string& path,
                  const PlyReadOptions& options, bool file_backed) {
  const char* data = static_cast<const char*>(data_ptr);
  if (size == 0 || data == nullptr) throw FileError(path, "empty file (missing PLY magic)");
  const Header h = ParseHeader(data, size, path);
  const std::size_t vertex_index = VertexElementIndex(h, path);
  const HeaderElement& vertex = h.elements[vertex_index];
  const std::size_t body = size - h.length;
  // Every record takes at least one byte (binary: >= 1 property; ASCII: >= 1 char), so a count
  // above the body size is corrupt; checking it first keeps allocations bounded.
  if (vertex.count > body && vertex.count > 0)
    throw FileError(path, "truncated data: " + std::to_string(vertex.count) + " vertices declared but only " +
                              std::to_string(body) + " bytes follow the header");

  // Columns as floats (the scene) plus, for ASCII and in-memory input, a copy of the records.
  const bool copies = h.format == PlySource::Format::kAscii || !file_backed;
  CheckMemoryEstimate(path + ": loading " + std::to_string(vertex.count) + " Gaussians",
                      double(vertex.count) * double(vertex.properties.size() + 11) * 4.0 + (copies ? double(body) : 0.0));
  Scene scene;
  scene.source_path = path;
  scene.source_format = "ply";
  const std::vector<Target> plan = PlanColumns(vertex, options, path, scene);
  auto src = std::make_shared<PlySource>();
  src->path = path;
  src->format = h.format;
  src->header.assign(data, h.length);
  for (std::size_t e = 0; e < h.elements.size(); ++e)
    if (e != vertex_index) src->extra_elements.push_back("element " + h.elements[e].name + " " + std::to_string(h.elements[e].count));
  const RecordLayout layout = DescribeRecords(vertex, *src);
  if (h.format != PlySource::Format::kAscii)
    ReadBinaryVertices(data, size, h, vertex_index, layout, plan, path, file_backed, *src);
  else
    ReadAsciiVertices(data, size, h, vertex_index, plan, path, *src);
  scene.ply = std::move(src);
  return scene;
}

}  // namespace

Scene ReadPlyFromMemory(const void* data, std::size_t size, const std::string& name,
                        const PlyReadOptions& options) {
  return ReadPlyImpl(data, size, name, options, /*file_backed=*/false);
}

Scene ReadPly(const std::string& path, const PlyReadOptions& options) {
  auto file = std::make_unique<io::MappedFile>(path);
  Scene scene = ReadPlyImpl(file->data(), file->size(), path, options, /*file_backed=*/true);
  io::UnmapInBackground(std::move(file));
  return scene;
}

}  // namespace al
