#include "al/metrics/directory.hpp"

#include <algorithm>
#include <map>
#include <sstream>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/io/image.hpp"
#include "al/metrics/mask_io.hpp"

namespace al::metrics {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

fs::path Resolve(const fs::path& dir, const fs::path& p) { return p.empty() || p.is_absolute() ? p : dir / p; }

bool IsDir(const fs::path& p) {
  std::error_code ec;
  return !p.empty() && fs::is_directory(p, ec);
}

bool IsFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

std::string Lower(std::string s) {
  for (auto& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Files of `dir` with extension `ext` (".png"/".json", case-insensitive), keyed by stem, in
// sorted file-name order.
std::map<std::string, fs::path> ListByStem(const fs::path& dir, const std::string& ext) {
  std::map<std::string, fs::path> out;
  if (!IsDir(dir)) return out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file(ec)) continue;
    if (Lower(entry.path().extension().string()) != ext) continue;
    out[entry.path().stem().string()] = entry.path();
  }
  if (ec) throw FileError(dir.string(), "cannot list directory: " + ec.message());
  return out;
}

std::string KeyOf(double threshold) {
  std::ostringstream s;
  s << threshold;
  return s.str();
}

// Detector mask for `stem`: <dir>/stem.png, else GroundedSAM <dir>/stem.json; false when absent.
bool LoadDetectorMask(const fs::path& dir, const std::string& stem, const std::string& seg_class, Gray8& out) {
  const fs::path png = dir / (stem + ".png"), js = dir / (stem + ".json");
  if (IsFile(png)) {
    out = LoadGray8Png(png.string());
    return true;
  }
  if (IsFile(js)) {
    out = LoadGroundedSamJson(js.string(), seg_class).mask;
    return true;
  }
  return false;
}

// Object mask > 0 for the depth metric and collateral damage; nullptr result when absent or unreadable.
bool LoadObjectMask(const fs::path& path, Mask& out, std::vector<std::string>& warnings) {
  if (!IsFile(path)) return false;
  try {
    out = Binarize(LoadGray8Png(path.string()), 0);
    return true;
  } catch (const Error& e) {
    warnings.push_back(std::string("unreadable object mask treated as missing: ") + e.what());
    return false;
  }
}

// A detector folder that does not exist is scored as all-empty detections (METRICS.md §2.1, the
// released behaviour); one warning names the absent folders. A folder the user named must exist.
void WarnAbsentDetectorFolders(const fs::path& before, const fs::path& after, bool named, DirectoryMetricsResult& r) {
  std::vector<std::string> absent;
  for (const fs::path* d : {&before, &after})
    if (!IsDir(*d)) absent.push_back(d->string());
  if (named && !absent.empty())
    throw FileError(absent[0], "not a directory (named with --seg-before / --seg-after)");
  r.counts["semantic"]["absent_detector_folders"] = absent;
  if (absent.empty()) return;
  std::string list = absent[0];
  if (absent.size() == 2) list += " and " + absent[1];
  r.warnings.push_back("semantic: no detector mask folder " + list +
                       ": every image is scored with an empty detection there (IoU 0), as the released "
                       "evaluator does; run GroundedSAM on the renders to score the detections");
}

void RunSemantic(const DirectoryMetricsOptions& o, DirectoryMetricsResult& r) {
  const fs::path objects = Resolve(o.dir, o.object_masks), before = Resolve(o.dir, o.seg_before),
                 after = Resolve(o.dir, o.seg_after);
  if (!IsDir(objects)) return r.skipped.push_back({"semantic", "no object mask directory " + objects.string()});
  WarnAbsentDetectorFolders(before, after, o.seg_folders_named, r);
  std::size_t unreadable = 0;
  for (const auto& [stem, path] : ListByStem(objects, ".png")) {
    Gray8 object;
    try {
      object = LoadGray8Png(path.string());
    } catch (const Error& e) {  // METRICS.md §2.1: an unreadable object mask skips the image
      ++unreadable;
      r.warnings.push_back(std::string("semantic: skipped image: ") + e.what());
      continue;
    }
    Gray8 pre, post;
    const bool has_pre = LoadDetectorMask(before, stem, o.seg_class, pre);
    const bool has_post = LoadDetectorMask(after, stem, o.seg_class, post);
    r.semantic.push_back(
        ComputeSemantic(object, has_pre ? &pre : nullptr, has_post ? &post : nullptr, path.filename().string()));
  }
  r.ran_semantic = true;
  r.semantic_summary = SummarizeSemantic(r.semantic, o.semantic);
  r.counts["semantic"].update({{"images", r.semantic.size()},
                               {"unreadable_object_masks", unreadable},
                               {"missing_before", r.semantic_summary.missing_before},
                               {"missing_after", r.semantic_summary.missing_after}});
}

DepthRecord ScoreDepthPair(const std::string& stem, const Gray8& d1, const Gray8& d2, const Mask* object,
                           const DirectoryMetricsOptions& o) {
  const DepthChange change = DepthChange8Bit(d1, d2, o.ght, o.depth_holes);
  DepthRecord rec;
  rec.image = stem;
  rec.score = ScoreDepthChange(object, change.changed);
  rec.threshold = change.threshold;
  rec.constant = change.constant;
  rec.trust = AssessDepthTrust(object, change, o.trust);
  rec.holes_before = change.holes_before;
  rec.holes_after = change.holes_after;
  return rec;
}

void RunDepth(const DirectoryMetricsOptions& o, DirectoryMetricsResult& r) {
  const fs::path before = Resolve(o.dir, o.depth_before), after = Resolve(o.dir, o.depth_after),
                 objects = Resolve(o.dir, o.object_masks);
  if (!IsDir(before) || !IsDir(after))
    return r.skipped.push_back({"depth", "no depth directories " + before.string() + " and " + after.string()});
  const auto after_files = ListByStem(after, ".png");
  const auto before_files = ListByStem(before, ".png");
  std::size_t missing_after = 0, missing_before = 0, non_8bit = 0;
  for (const auto& [stem, path] : after_files) missing_before += before_files.count(stem) == 0;
  for (const auto& [stem, path] : before_files) {
    const auto it = after_files.find(stem);
    if (it == after_files.end()) {
      ++missing_after;
      continue;
    }
    bool lossy1 = false, lossy2 = false;
    const PngData png1 = ReadPng(path.string()), png2 = ReadPng(it->second.string());
    for (const PngData* p : {&png1, &png2})
      if (p->bit_depth != 8 || p->channels != 1) ++non_8bit;
    const Gray8 d1 = ToLuma8(png1, &lossy1), d2 = ToLuma8(png2, &lossy2);
    if (lossy1 || lossy2)
      r.warnings.push_back("depth " + stem + ": 16-bit or colour depth PNG converted as PIL convert(\"L\") (values clipped)");
    if (d1.width != d2.width || d1.height != d2.height)
      throw FileError(it->second.string(), "depth image size differs from " + path.string());
    Mask object;
    const bool has_object = LoadObjectMask(objects / (stem + ".png"), object, r.warnings);
    r.depth.push_back(ScoreDepthPair(stem, d1, d2, has_object ? &object : nullptr, o));
  }
  if (non_8bit) r.warnings.push_back("depth: " + std::to_string(non_8bit) + " depth PNG(s) are not 8-bit grey");
  r.ran_depth = true;
  r.depth_summary = SummarizeDepth(r.depth);
  r.counts["depth"] = {{"images", r.depth.size()},          {"missing_after", missing_after},
                       {"missing_before", missing_before},  {"missing_object_masks", r.depth_summary.missing_object},
                       {"constant_masks", r.depth_summary.constant_masks}, {"non_8bit_inputs", non_8bit},
                       {"flagged_images", r.depth_summary.flagged.size()}};
}

// SAM segment lists of a side, keyed by stem: per-image X.json parsed lazily, merged.json eagerly.
class SamSide {
 public:
  explicit SamSide(const fs::path& dir) {
    for (const auto& [stem, path] : ListByStem(dir, ".json")) {
      if (stem == "merged") {
        for (auto& [key, list] : LoadSamJson(path.string())) merged_[key] = std::move(list);
      } else {
        files_[stem] = path;
      }
    }
  }
  bool empty() const { return files_.empty() && merged_.empty(); }
  std::vector<std::string> Stems() const {
    std::vector<std::string> s;
    for (const auto& [k, v] : files_) s.push_back(k);
    for (const auto& [k, v] : merged_)
      if (!files_.count(k)) s.push_back(k);
    std::sort(s.begin(), s.end());
    return s;
  }
  bool Has(const std::string& stem) const { return files_.count(stem) || merged_.count(stem); }
  std::vector<Mask> Load(const std::string& stem) const {
    if (const auto it = files_.find(stem); it != files_.end()) {
      auto lists = LoadSamJson(it->second.string());
      if (lists.count("")) return std::move(lists[""]);
      if (lists.count(stem)) return std::move(lists[stem]);
      throw FileError(it->second.string(), "holds no segment list for " + stem);
    }
    return merged_.at(stem);
  }

 private:
  std::map<std::string, fs::path> files_;
  std::map<std::string, std::vector<Mask>> merged_;
};

void RunSimSam(const DirectoryMetricsOptions& o, DirectoryMetricsResult& r) {
  const fs::path a_dir = Resolve(o.dir, o.sam_a), b_dir = Resolve(o.dir, o.sam_b),
                 objects = Resolve(o.dir, o.object_masks);
  const SamSide a(a_dir);
  if (a.empty()) return r.skipped.push_back({"sim_sam", "no SAM segment lists (*.json) in " + a_dir.string()});
  const SamSide b(b_dir);
  if (b.empty()) return r.skipped.push_back({"sim_sam", "no SAM segment lists (*.json) in " + b_dir.string()});
  std::size_t missing_b = 0, missing_object = 0;
  for (const std::string& stem : a.Stems()) {
    if (!b.Has(stem)) {
      ++missing_b;
      continue;
    }
    // Parse both lists first: a malformed file is bad input even when the image is then skipped.
    const std::vector<Mask> segments_a = a.Load(stem), segments_b = b.Load(stem);
    const fs::path object_path = objects / (stem + ".png");
    if (!IsFile(object_path)) {
      ++missing_object;
      continue;
    }
    Gray8 object;
    try {
      object = LoadGray8Png(object_path.string());
    } catch (const Error& e) {
      ++missing_object;
      r.warnings.push_back(std::string("sim_sam: skipped image: ") + e.what());
      continue;
    }
    r.sam.push_back({stem, ComputeSimSam(object, segments_a, segments_b, o.sim_sam)});
  }
  r.ran_sam = true;
  r.sam_summary = SummarizeSimSam(r.sam, missing_b, missing_object);
  r.counts["sim_sam"] = {{"candidates", r.sam_summary.candidates},
                         {"scored", r.sam_summary.scored},
                         {"dropped_empty_side", r.sam_summary.dropped_empty_side},
                         {"missing_side_b", missing_b},
                         {"missing_object_masks", missing_object}};
}

void RunCollateral(const DirectoryMetricsOptions& o, DirectoryMetricsResult& r) {
  if (o.rgb_before.empty() || o.rgb_after.empty())
    return r.skipped.push_back({"collateral_psnr", "no RGB renders given (rgb_before / rgb_after)"});
  const fs::path before = Resolve(o.dir, o.rgb_before), after = Resolve(o.dir, o.rgb_after),
                 objects = Resolve(o.dir, o.object_masks);
  if (!IsDir(before)) throw FileError(before.string(), "not a directory");
  if (!IsDir(after)) throw FileError(after.string(), "not a directory");
  const auto after_files = ListByStem(after, ".png");
  std::size_t missing_after = 0;
  for (const auto& [stem, path] : ListByStem(before, ".png")) {
    const auto it = after_files.find(stem);
    if (it == after_files.end()) {
      ++missing_after;
      continue;
    }
    const RgbImage rgb1 = RgbFromPng(ReadPng(path.string())), rgb2 = RgbFromPng(ReadPng(it->second.string()));
    if (rgb1.width != rgb2.width || rgb1.height != rgb2.height)
      throw FileError(it->second.string(), "RGB render size differs from " + path.string());
    Mask object;
    const bool has_object = LoadObjectMask(objects / (stem + ".png"), object, r.warnings);
    r.collateral.push_back({stem, ComputeCollateralPsnr(rgb1, rgb2, has_object ? &object : nullptr)});
  }
  r.ran_collateral = true;
  r.counts["collateral_psnr"] = {{"images", r.collateral.size()}, {"missing_after", missing_after}};
}

json MeanStdJson(const MeanStd& m) { return {{"mean", m.mean}, {"std", m.std}, {"count", m.count}}; }

}  // namespace

std::string DirectoryMetricsOptions::Check() const {
  if (dir.empty()) return "no scene directory given";
  if (!IsDir(dir)) return dir.string() + ": not a directory";
  if (!(sim_sam.min_object_iou >= 0 && sim_sam.min_object_iou <= 1)) return "sim_SAM filter IoU must be in [0, 1]";
  if (!(ght.nu >= 0) || !(ght.tau >= 0)) return "GHT nu and tau must be >= 0";
  return trust.Check();
}

json DirectoryMetricsOptions::ToJson() const {
  return {{"dir", dir.string()},
          {"object_masks", object_masks.string()},
          {"seg_before", seg_before.string()},
          {"seg_after", seg_after.string()},
          {"seg_class", seg_class},
          {"depth_before", depth_before.string()},
          {"depth_after", depth_after.string()},
          {"depth_mode", "8bit"},
          {"depth_holes", DepthHolesName(depth_holes)},
          {"depth_trust", trust.ToJson()},
          {"sam_a", sam_a.string()},
          {"sam_b", sam_b.string()},
          {"rgb_before", rgb_before.string()},
          {"rgb_after", rgb_after.string()},
          {"sam_min_iou", sim_sam.min_object_iou},
          {"sam_object_threshold", sim_sam.object_threshold},
          {"ght", {{"nu", ght.nu}, {"tau", ght.tau}, {"kappa", ght.kappa}, {"omega", ght.omega}}},
          {"acc_seg_thresholds", semantic.acc_seg_thresholds},
          {"table_thresholds", semantic.table_thresholds}};
}

SimSamSummary SummarizeSimSam(const std::vector<SimSamRecord>& records, std::size_t missing_side_b,
                              std::size_t missing_object) {
  SimSamSummary s;
  s.candidates = records.size();
  s.missing_side_b = missing_side_b;
  s.missing_object = missing_object;
  std::vector<double> values;
  for (const auto& rec : records) {
    if (rec.result.scored) values.push_back(rec.result.sim_sam);
    else ++s.dropped_empty_side;
  }
  s.scored = values.size();
  s.sim_sam = ComputeMeanStd(values);
  return s;
}

DirectoryMetricsResult EvaluateDirectory(const DirectoryMetricsOptions& options) {
  if (const std::string problem = options.Check(); !problem.empty()) throw Error(problem);
  DirectoryMetricsResult r;
  r.depth_holes = options.depth_holes;
  RunSemantic(options, r);
  RunDepth(options, r);
  RunSimSam(options, r);
  RunCollateral(options, r);
  return r;
}

json SemanticJson(const std::vector<SemanticRecord>& records) {
  json out = json::array();
  for (const auto& r : records)
    out.push_back({{"image_name", r.image_name}, {"iou_before", r.iou_before}, {"iou_after", r.iou_after},
                   {"iou_drop", r.iou_drop},     {"acc_before", r.acc_before}, {"acc_after", r.acc_after},
                   {"acc_diff", r.acc_diff}});
  return out;
}

json DepthJson(const std::vector<DepthRecord>& records) {
  json out = json::array();
  for (const auto& r : records)
    out.push_back({{"image", r.image},
                   {"acc_delta_depth", r.score.acc_delta_depth},
                   {"iou", r.score.iou},
                   {"collateral_depth", r.score.collateral_depth},
                   {"ght_threshold", r.threshold},
                   {"constant_mask", r.constant},
                   {"object_mask_missing", r.score.missing_object},
                   {"hole_pixels", {{"before", r.holes_before}, {"after_only", r.holes_after}}},
                   {"trust", r.trust.ToJson()}});
  return out;
}

json SimSamJson(const std::vector<SimSamRecord>& records) {
  json out = json::object();
  for (const auto& r : records) {
    if (!r.result.scored) continue;
    json matches = json::array();
    for (const auto& m : r.result.matches) matches.push_back({{"gt_idx", m.gt_idx}, {"sam_idx", m.sam_idx}, {"iou", m.iou}});
    out[r.image] = {{"matches", matches}, {"sim_sam", r.result.sim_sam}, {"n_gt", r.result.n_gt}, {"n_sam", r.result.n_sam}};
  }
  return out;
}

json CollateralJson(const std::vector<CollateralRecord>& records) {
  json out = json::array();
  for (const auto& r : records)
    out.push_back({{"image", r.image},
                   {"collateral_psnr", r.psnr.psnr ? json(*r.psnr.psnr) : json(nullptr)},
                   {"identical", r.psnr.identical},
                   {"pixels", r.psnr.pixels}});
  return out;
}

json SummaryJson(const DirectoryMetricsResult& r) {
  json out = json::object();
  if (r.ran_semantic) {
    const auto& s = r.semantic_summary;
    json seg = json::object(), table = json::object();
    for (const auto& t : s.acc_seg) seg[KeyOf(t.threshold)] = t.value;
    for (const auto& t : s.acc_iou_post_above) table[KeyOf(t.threshold)] = t.value;
    out["semantic"] = {{"n_images", s.images},
                       {"mean_iou_before", s.iou_before},
                       {"mean_iou_after", s.iou_after},
                       {"mean_iou_drop", s.iou_drop},
                       {"mean_acc_before", s.acc_before},
                       {"mean_acc_after", s.acc_after},
                       {"mean_acc_diff", s.acc_diff},
                       {"acc_seg", seg},
                       {"acc_iou_post_above_percent", table},
                       {"missing_before", s.missing_before},
                       {"missing_after", s.missing_after}};
  }
  if (r.ran_depth) {
    out["depth"] = r.depth_summary.ToJson();
    out["depth"]["mode"] = "8bit";
    out["depth"]["depth_holes"] = DepthHolesName(r.depth_holes);
  }
  if (r.ran_sam) {
    const auto& s = r.sam_summary;
    out["sim_sam"] = {{"n_scored", s.scored},
                      {"mean_sim_sam", s.sim_sam.mean},
                      {"std_sim_sam", s.sim_sam.std},
                      {"dropped_empty_side", s.dropped_empty_side},
                      {"missing_side_b", s.missing_side_b},
                      {"missing_object_masks", s.missing_object},
                      {"direction",
                       "side A (gt) vs side B (sam): higher = more similar; with A = before-removal segments, "
                       "lower = better removal (paper)"}};
  }
  if (r.ran_collateral) {
    std::vector<double> psnr;
    std::size_t identical = 0;
    for (const auto& c : r.collateral) {
      if (c.psnr.psnr) psnr.push_back(*c.psnr.psnr);
      identical += c.psnr.identical;
    }
    out["collateral_psnr"] = {{"n_images", r.collateral.size()}, {"psnr", MeanStdJson(ComputeMeanStd(psnr))},
                              {"identical", identical}};
  }
  json skipped = json::array();
  for (const auto& s : r.skipped) skipped.push_back({{"metric", s.metric}, {"reason", s.reason}});
  out["skipped"] = skipped;
  return out;
}

std::vector<fs::path> WriteDirectoryMetrics(const DirectoryMetricsResult& r, const fs::path& out_dir) {
  EnsureDirectory(out_dir);
  std::vector<fs::path> written;
  auto write = [&](const char* name, const json& j) {
    WriteFileAtomically(out_dir / name, j.dump(2) + "\n");
    written.push_back(out_dir / name);
  };
  if (r.ran_semantic) write("semantic.json", SemanticJson(r.semantic));
  if (r.ran_depth) write("depth.json", DepthJson(r.depth));
  if (r.ran_sam) write("sam.json", SimSamJson(r.sam));
  if (r.ran_collateral) write("collateral.json", CollateralJson(r.collateral));
  return written;
}

}  // namespace al::metrics
