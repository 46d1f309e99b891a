// Removal sets (FORMATS.md §2.3-2.4): .npy bool/uint8 mask or integer indices, .txt indices,
// or a subset PLY matched back to scene indices by exact float bit patterns.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/scene/scene.hpp"

namespace al {

enum class RemovedIs { kRemoved, kRemaining };

struct RemovalLoadOptions {
  RemovedIs removed_is = RemovedIs::kRemoved;
  std::size_t max_unmatched = 0;  // subset PLY rows that may stay unmatched
  double match_tolerance = 0.0;   // > 0 enables the tolerance pass
  bool gc_polarity = false;       // --method gc: float .npy with 0 = removed accepted
};

struct RemovalSet {
  std::vector<bool> removed;  // N
  std::size_t num_removed = 0;
  // Statistics for the report: input kind, duplicates, matching passes, unmatched, ambiguous.
  nlohmann::json stats = nlohmann::json::object();
  std::vector<std::string> warnings;
};

// Throws al::Error naming the file (out-of-range indices, wrong length, ambiguous 0/1 integers,
// float arrays without gc polarity, unmatched rows above max_unmatched, ...).
RemovalSet LoadRemovalSet(const std::string& path, const Scene& scene, const RemovalLoadOptions& options = {});

// Matching of a subset scene to the full scene (exposed for tests): index per subset row, -1 unmatched.
struct SubsetMatch {
  std::vector<std::int64_t> scene_index;
  std::size_t matched_in_order = 0, matched_by_hash = 0, matched_by_tolerance = 0, unmatched = 0, ambiguous = 0;
};
SubsetMatch MatchSubset(const Scene& scene, const Scene& subset, double match_tolerance = 0.0);

// Index list helpers.
std::vector<std::int64_t> MaskToIndices(const std::vector<bool>& mask);
void WriteIndexText(const std::string& path, const std::vector<std::int64_t>& indices, const std::string& comment = "");

}  // namespace al
