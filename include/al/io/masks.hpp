// Removal sets (FORMATS.md §2.3-2.4): .npy bool/uint8 mask or integer indices, .txt indices,
// or a subset PLY matched back to scene indices by exact float bit patterns.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/io/npy.hpp"
#include "al/scene/scene.hpp"

namespace al {

enum class RemovedIs { kRemoved, kRemaining };

struct RemovalLoadOptions {
  // Polarity of the file's rows. kRemaining complements the loaded set for every kind (a subset
  // PLY of the remaining scene, or a mask/index list of remaining rows).
  RemovedIs removed_is = RemovedIs::kRemoved;
  std::size_t max_unmatched = 0;  // subset PLY rows that may stay unmatched
  double match_tolerance = 0.0;   // > 0 enables the tolerance pass
  bool gc_polarity = false;       // --method gc: float .npy with 0 = removed accepted
};

struct RemovalSet {
  std::vector<bool> removed;  // N
  std::size_t num_removed = 0;
  // Statistics for the report: {"kind": "mask|indices|txt|subset_ply|gc_float", "num_input_rows",
  // "duplicates", "matched_in_order", "matched_by_hash", "matched_by_tolerance", "unmatched",
  // "ambiguous", "removed_is", "num_removed"} (+ "scene_rows" for subset PLYs).
  nlohmann::json stats = nlohmann::json::object();
  std::vector<std::string> warnings;
};

// Throws al::Error naming the file (out-of-range indices, wrong length, ambiguous 0/1 integers,
// float arrays without gc polarity, unmatched rows above max_unmatched, ...).
RemovalSet LoadRemovalSet(const std::string& path, const Scene& scene, const RemovalLoadOptions& options = {});

// The .npy interpretation behind LoadRemovalSet, for an array already in memory (the Python module
// hands NumPy arrays over without a copy): bool/uint8 mask of shape (N,), integer indices, or
// (gc_polarity) floats with 0 = removed; then the removed_is polarity. `name` prefixes errors.
RemovalSet RemovalSetFromArray(const NpyArray& array, const std::string& name, std::size_t num_gaussians,
                               const RemovalLoadOptions& options = {});

// The .txt parser behind LoadRemovalSet (in memory; for fuzzing): one index per line, blank lines
// and '#' comments ignored, indices checked against [0, num_gaussians). `name` prefixes errors.
RemovalSet RemovalSetFromIndexText(const std::string& text, const std::string& name, std::size_t num_gaussians);

// Matching of a subset scene to the full scene (exposed for tests): index per subset row, -1 unmatched.
// Key = float32 bits of x y z [opacity] [scale_0..2] [rot_0..3] [f_dc_0..2], the optional groups
// used when Scene::has_* is true in both scenes. Pass 1 walks both in order and keeps the matched
// prefix up to the first subset row it cannot find; pass 2 gives each remaining row the smallest
// unused scene index with its key; pass 3 (match_tolerance > 0) the nearest unused centre within
// the tolerance. `ambiguous` counts subset rows whose key occurs more than once in the scene.
struct SubsetMatch {
  std::vector<std::int64_t> scene_index;
  std::size_t matched_in_order = 0, matched_by_hash = 0, matched_by_tolerance = 0, unmatched = 0, ambiguous = 0;
};
SubsetMatch MatchSubset(const Scene& scene, const Scene& subset, double match_tolerance = 0.0);

// Index list helpers.
std::vector<std::int64_t> MaskToIndices(const std::vector<bool>& mask);
// One index per line, atomically; each line of `comment` (if any) is written first as "# <line>".
void WriteIndexText(const std::string& path, const std::vector<std::int64_t>& indices, const std::string& comment = "");

}  // namespace al
