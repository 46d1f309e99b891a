#include "al/eval/segmentations.hpp"

#include <filesystem>

#include "al/core/error.hpp"
#include "al/metrics/mask_io.hpp"

namespace al::eval {

namespace fs = std::filesystem;

namespace {
bool IsFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}
}  // namespace

bool LoadDetectorMask(const std::string& dir, const std::string& stem, const std::string& seg_class,
                      metrics::Gray8& out) {
  const fs::path png = fs::path(dir) / (stem + ".png"), js = fs::path(dir) / (stem + ".json");
  if (IsFile(png)) {
    out = metrics::LoadGray8Png(png.string());
    return true;
  }
  if (IsFile(js)) {
    out = metrics::LoadGroundedSamJson(js.string(), seg_class).mask;
    return true;
  }
  return false;
}

bool SamLists::Load(const std::string& stem, std::vector<metrics::Mask>& out) {
  const fs::path file = fs::path(dir_) / (stem + ".json");
  if (IsFile(file)) {
    auto lists = metrics::LoadSamJson(file.string());
    if (lists.count("")) out = std::move(lists[""]);
    else if (lists.count(stem)) out = std::move(lists[stem]);
    else throw FileError(file.string(), "holds no segment list for " + stem);
    return true;
  }
  if (!merged_loaded_) {
    merged_loaded_ = true;
    const fs::path merged = fs::path(dir_) / "merged.json";
    if (IsFile(merged)) merged_ = metrics::LoadSamJson(merged.string());
  }
  const auto it = merged_.find(stem);
  if (it == merged_.end()) return false;
  out = it->second;
  return true;
}

}  // namespace al::eval
