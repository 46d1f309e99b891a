// Segmentations of the evaluator's renders, made by external tools and joined by view name
// (METRICS.md §1): detector masks (GroundedSAM-style) and SAM segment lists.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "al/metrics/mask.hpp"

namespace al::eval {

// <dir>/<stem>.png, else GroundedSAM <dir>/<stem>.json filtered by seg_class; false when absent
// (a missing detection is an empty mask, METRICS.md §2). Corrupt files throw al::Error.
bool LoadDetectorMask(const std::string& dir, const std::string& stem, const std::string& seg_class,
                      metrics::Gray8& out);

// SAM segment lists of one folder: <dir>/<stem>.json per view, or the legacy merged.json
// {image_name: [segments]} (parsed once, on first use).
class SamLists {
 public:
  explicit SamLists(std::string dir) : dir_(std::move(dir)) {}
  // false when the folder holds no list for the view.
  bool Load(const std::string& stem, std::vector<metrics::Mask>& out);

 private:
  std::string dir_;
  bool merged_loaded_ = false;
  std::map<std::string, std::vector<metrics::Mask>> merged_;
};

}  // namespace al::eval
