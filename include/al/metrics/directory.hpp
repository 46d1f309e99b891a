// Metrics on renders made by another pipeline, read from the released per-scene layout
// (METRICS.md §1): masks/X.png, gsam2/{before,after}/mask/X.png (or GroundedSAM X.json),
// depth/{before,after}/X.png, masks/X.json and sam/after/X.json (or merged.json), joined by stem.
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/metrics/collateral.hpp"
#include "al/metrics/depth.hpp"
#include "al/metrics/semantic.hpp"
#include "al/metrics/sim_sam.hpp"

namespace al::metrics {

struct DirectoryMetricsOptions {
  std::filesystem::path dir;  // the scene directory; relative sub-paths below are taken from it
  std::filesystem::path object_masks = "masks";
  std::filesystem::path seg_before = "gsam2/before/mask", seg_after = "gsam2/after/mask";
  // The user named seg_before / seg_after: an absent folder is then a typo (an error), not the
  // released evaluator's "no detections" default that the standard layout gets.
  bool seg_folders_named = false;
  std::filesystem::path depth_before = "depth/before", depth_after = "depth/after";
  std::filesystem::path sam_a = "masks";      // side A ("gt" in sam.json): SAM on the real photos
  std::filesystem::path sam_b = "sam/after";  // side B ("sam"): SAM on the after-removal renders
  std::filesystem::path rgb_before, rgb_after;  // optional RGB renders for collateral PSNR
  std::string seg_class;  // GroundedSAM JSON class to keep (empty = every instance)
  SemanticOptions semantic;
  SimSamOptions sim_sam;
  GhtOptions ght;
  DepthHoles depth_holes = DepthHoles::kBefore;  // released behaviour (METRICS.md §4 step 1)
  DepthTrustOptions trust;
  std::string Check() const;  // empty when valid, else the problem
  nlohmann::json ToJson() const;  // every effective option (report.json "params")
};

struct SimSamRecord {
  std::string image;
  SimSamResult result;
};
struct SimSamSummary {
  MeanStd sim_sam;  // over scored images
  std::size_t candidates = 0, scored = 0, dropped_empty_side = 0, missing_side_b = 0, missing_object = 0;
};
SimSamSummary SummarizeSimSam(const std::vector<SimSamRecord>& records, std::size_t missing_side_b,
                              std::size_t missing_object);

struct CollateralRecord {
  std::string image;
  CollateralPsnr psnr;
};

struct SkippedMetric {
  std::string metric, reason;
};

struct DirectoryMetricsResult {
  std::vector<SemanticRecord> semantic;
  SemanticSummary semantic_summary;
  std::vector<DepthRecord> depth;
  DepthSummary depth_summary;
  std::vector<SimSamRecord> sam;  // scored and dropped images, in stem order
  SimSamSummary sam_summary;
  std::vector<CollateralRecord> collateral;
  std::vector<SkippedMetric> skipped;
  nlohmann::json counts = nlohmann::json::object();  // skipped/missing files per metric
  std::vector<std::string> warnings;
  bool ran_semantic = false, ran_depth = false, ran_sam = false, ran_collateral = false;
  DepthHoles depth_holes = DepthHoles::kBefore;  // the rule the depth records were computed with
};

// Throws al::Error "<file>: <problem>" on unreadable inputs other than object masks (an unreadable
// object mask skips the image for the semantic metrics and is counted, METRICS.md §2). With object
// masks present, absent detector folders score every image with empty detections (warned once).
DirectoryMetricsResult EvaluateDirectory(const DirectoryMetricsOptions& options);

// Released per-image JSON (field names of METRICS.md): semantic.json list, depth.json list,
// sam.json {image: {matches, sim_sam, n_gt, n_sam}} (scored images only), collateral.json.
nlohmann::json SemanticJson(const std::vector<SemanticRecord>& records);
nlohmann::json DepthJson(const std::vector<DepthRecord>& records);
nlohmann::json SimSamJson(const std::vector<SimSamRecord>& records);
nlohmann::json CollateralJson(const std::vector<CollateralRecord>& records);
// Pooled summaries and skip reasons (report.json "metrics" section).
nlohmann::json SummaryJson(const DirectoryMetricsResult& result);

// Writes the per-image files of the metrics that ran into out_dir (atomically).
std::vector<std::filesystem::path> WriteDirectoryMetrics(const DirectoryMetricsResult& result,
                                                         const std::filesystem::path& out_dir);

}  // namespace al::metrics
