// Loading the removed set (FORMATS.md §2.3-2.4): .npy masks or indices, .txt indices, subset PLY.
#include "al/io/masks.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/io/npy.hpp"
#include "al/io/ply.hpp"

namespace al {
namespace {

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

nlohmann::json BaseStats(const std::string& kind, std::size_t rows) {
  return {{"kind", kind},          {"num_input_rows", rows}, {"duplicates", 0},
          {"matched_in_order", 0}, {"matched_by_hash", 0},   {"matched_by_tolerance", 0},
          {"unmatched", 0},        {"ambiguous", 0}};
}

// The polarity flag applies to every kind: a list of remaining rows is complemented.
RemovalSet ApplyPolarity(RemovalSet r, const RemovalLoadOptions& options) {
  if (options.removed_is == RemovedIs::kRemaining) r.removed.flip();
  r.num_removed = static_cast<std::size_t>(std::count(r.removed.begin(), r.removed.end(), true));
  r.stats["removed_is"] = options.removed_is == RemovedIs::kRemaining ? "remaining" : "removed";
  r.stats["num_removed"] = r.num_removed;
  return r;
}

// Marks indices as removed; `where(k)` describes input item k for error messages.
template <typename Where>
void ApplyIndices(const std::string& path, const std::vector<std::int64_t>& idx, std::size_t n,
                  std::vector<bool>& removed, std::size_t& duplicates, Where where) {
  for (std::size_t k = 0; k < idx.size(); ++k) {
    const std::int64_t v = idx[k];
    if (v < 0 || static_cast<std::uint64_t>(v) >= n)
      throw FileError(path, "index " + std::to_string(v) + " out of range [0, " + std::to_string(n) + ") at " +
                                where(k));
    if (removed[static_cast<std::size_t>(v)]) ++duplicates;
    removed[static_cast<std::size_t>(v)] = true;
  }
}

RemovalSet LoadNpy(const std::string& path, const Scene& scene, const RemovalLoadOptions& opt) {
  return RemovalSetFromArray(ReadNpy(path), path, scene.size(), opt);
}

RemovalSet LoadTxt(const std::string& path, const Scene& scene) {
  return RemovalSetFromIndexText(ReadInputFile(path), path, scene.size());
}

}  // namespace

RemovalSet RemovalSetFromArray(const NpyArray& a, const std::string& path, std::size_t n,
                               const RemovalLoadOptions& opt) {
  if (a.shape.size() != 1)
    throw FileError(path, "expected a 1-D array (mask of shape (N,) or indices of shape (M,)), got " +
                              std::to_string(a.shape.size()) + " dimensions");
  const std::size_t len = a.size();
  RemovalSet r;
  r.removed.assign(n, false);
  if (a.is_bool() || a.descr == "u1") {
    if (len != n)
      throw FileError(path, "mask length " + std::to_string(len) + " does not match the scene's " +
                                std::to_string(n) + " Gaussians");
    for (std::size_t i = 0; i < n; ++i) r.removed[i] = a.data[i] != 0;
    r.stats = BaseStats("mask", len);
  } else if (a.is_integer()) {
    const std::vector<std::int64_t> idx = a.ToInt64();
    if (len == n && n > 0 && std::all_of(idx.begin(), idx.end(), [](std::int64_t v) { return v == 0 || v == 1; }))
      throw FileError(path, "integer array of length N = " + std::to_string(n) +
                                " holding only 0 and 1 is ambiguous (a mask or indices?): save a mask as dtype "
                                "bool/uint8, or indices without this pattern");
    std::size_t dup = 0;
    ApplyIndices(path, idx, n, r.removed, dup, [](std::size_t k) { return "position " + std::to_string(k); });
    // N integers with repeats cannot be an index list of a subset: it is per-Gaussian data (labels,
    // a class map) passed by mistake, and reading it as indices would be a silent wrong answer.
    if (len == n && dup > 0)
      throw FileError(path, "integer array of length N = " + std::to_string(n) + " with " + std::to_string(dup) +
                                " repeated values is not an index list (per-Gaussian labels?): pass the "
                                "removed set as a bool mask or as distinct indices");
    r.stats = BaseStats("indices", len);
    r.stats["duplicates"] = dup;
    if (dup) r.warnings.push_back(path + ": " + std::to_string(dup) + " duplicate indices ignored");
  } else {
    if (!opt.gc_polarity)
      throw FileError(path, "float arrays are rejected (polarity is never guessed): save a bool mask "
                            "(True = removed) or integer indices, or use --method gc for GaussianCut's "
                            "0 = removed arrays");
    if (len != n)
      throw FileError(path, "array length " + std::to_string(len) + " does not match the scene's " +
                                std::to_string(n) + " Gaussians");
    for (std::size_t i = 0; i < n; ++i) r.removed[i] = a.At(i) == 0.0;  // GC polarity: exactly 0 = removed
    r.stats = BaseStats("gc_float", len);
  }
  return ApplyPolarity(std::move(r), opt);
}

RemovalSet RemovalSetFromIndexText(const std::string& text, const std::string& path, std::size_t n) {
  std::istringstream in(text);
  std::vector<std::int64_t> idx;
  std::vector<std::size_t> line_of;
  std::string line;
  std::size_t lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    const auto b = line.find_first_not_of(" \t\r\v\f");
    if (b == std::string::npos) continue;
    const auto e = line.find_last_not_of(" \t\r\v\f");
    const std::string tok = line.substr(b, e - b + 1);
    std::int64_t v = 0;
    const char* first = tok.data();
    if (*first == '+') ++first;
    const auto [ptr, ec] = std::from_chars(first, tok.data() + tok.size(), v);
    if (ec == std::errc::result_out_of_range)
      throw FileError(path, "line " + std::to_string(lineno) + ": index '" + tok + "' out of range");
    if (ec != std::errc() || ptr != tok.data() + tok.size())
      throw FileError(path, "line " + std::to_string(lineno) + ": '" + tok +
                                "' is not an integer index (expected one 0-based index per line)");
    idx.push_back(v);
    line_of.push_back(lineno);
  }
  RemovalSet r;
  r.removed.assign(n, false);
  std::size_t dup = 0;
  ApplyIndices(path, idx, n, r.removed, dup, [&](std::size_t k) { return "line " + std::to_string(line_of[k]); });
  r.stats = BaseStats("txt", idx.size());
  r.stats["duplicates"] = dup;
  if (dup) r.warnings.push_back(path + ": " + std::to_string(dup) + " duplicate indices ignored");
  r.num_removed = static_cast<std::size_t>(std::count(r.removed.begin(), r.removed.end(), true));
  return r;
}

namespace {

RemovalSet LoadSubsetPly(const std::string& path, const Scene& scene, const RemovalLoadOptions& opt) {
  PlyReadOptions po;
  po.feature_prefix = "none";
  po.require_scales = false;
  const Scene subset = ReadPly(path, po);
  const SubsetMatch m = MatchSubset(scene, subset, opt.match_tolerance);
  RemovalSet r;
  r.stats = BaseStats("subset_ply", subset.size());
  r.stats["matched_in_order"] = m.matched_in_order;
  r.stats["matched_by_hash"] = m.matched_by_hash;
  r.stats["matched_by_tolerance"] = m.matched_by_tolerance;
  r.stats["unmatched"] = m.unmatched;
  r.stats["ambiguous"] = m.ambiguous;
  r.stats["scene_rows"] = scene.size();
  if (m.unmatched > 0) {
    std::ostringstream rows;
    rows.precision(9);
    std::size_t shown = 0;
    for (std::size_t j = 0; j < m.scene_index.size() && shown < 5; ++j) {
      if (m.scene_index[j] >= 0) continue;
      rows << (shown ? "; " : "") << "row " << j << " (x=" << subset.means(j, 0) << " y=" << subset.means(j, 1)
           << " z=" << subset.means(j, 2) << ")";
      ++shown;
    }
    const std::string msg = std::to_string(m.unmatched) + " of " + std::to_string(subset.size()) +
                            " subset rows match no scene row (first: " + rows.str() +
                            "); a different iteration, modified or re-sorted file?";
    if (m.unmatched > opt.max_unmatched)
      throw FileError(path, msg + " Allowed: --max-unmatched " + std::to_string(opt.max_unmatched));
    r.warnings.push_back(path + ": " + msg + " They are ignored" +
                         (opt.removed_is == RemovedIs::kRemaining ? " (and count as removed)." : "."));
  }
  if (m.ambiguous > 0)
    r.warnings.push_back(path + ": " + std::to_string(m.ambiguous) +
                         " subset rows have keys shared by several scene rows (exact clones); the smallest "
                         "unused index was taken");
  r.removed.assign(scene.size(), false);
  for (std::int64_t i : m.scene_index)
    if (i >= 0) r.removed[static_cast<std::size_t>(i)] = true;
  return r;
}

}  // namespace

RemovalSet LoadRemovalSet(const std::string& path, const Scene& scene, const RemovalLoadOptions& options) {
  const std::string ext = Lower(std::filesystem::path(path).extension().string());
  RemovalSet r;
  if (ext == ".npy") {
    return LoadNpy(path, scene, options);  // polarity applied by RemovalSetFromArray
  } else if (ext == ".txt") {
    r = LoadTxt(path, scene);
  } else if (ext == ".ply") {
    r = LoadSubsetPly(path, scene, options);
  } else {
    throw FileError(path, "unknown removed-set format '" + ext + "' (expected .npy, .txt or .ply)");
  }
  return ApplyPolarity(std::move(r), options);
}

std::vector<std::int64_t> MaskToIndices(const std::vector<bool>& mask) {
  std::vector<std::int64_t> out;
  for (std::size_t i = 0; i < mask.size(); ++i)
    if (mask[i]) out.push_back(static_cast<std::int64_t>(i));
  return out;
}

void WriteIndexText(const std::string& path, const std::vector<std::int64_t>& indices, const std::string& comment) {
  std::string text;
  if (!comment.empty()) {
    std::istringstream lines(comment);
    std::string l;
    while (std::getline(lines, l)) text += "# " + l + "\n";
  }
  text.reserve(text.size() + indices.size() * 8);
  for (std::int64_t i : indices) {
    text += std::to_string(i);
    text += '\n';
  }
  WriteFileAtomically(path, text);
}

}  // namespace al
