// acc_Δdepth (METRICS.md §4–§6): the published 8-bit pipeline (inverted min–max LUT image, GHT,
// `byte < t`), the project's float mode, and the float → 8-bit depth conversion of §6.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "al/metrics/depth_trust.hpp"
#include "al/metrics/mask.hpp"
#include "al/metrics/stats.hpp"

namespace al::metrics {

// Generalized Histogram Thresholding (Barron, ECCV 2020) parameters; defaults = published values.
struct GhtOptions {
  double nu = 1000, tau = 300, kappa = 0, omega = 0;
  void Check() const;  // nu, tau, kappa >= 0; omega in [0, 1]
};

using Histogram256 = std::array<std::int64_t, 256>;

// Threshold t over bin centres 0..255: the mean of all split indices i (class 0 = bins ≤ i) whose
// objective equals the maximum exactly (METRICS.md §4 step 4). An empty histogram ties on every
// split (t = 127).
double GhtThreshold(const Histogram256& histogram, const GhtOptions& options = {});
// The per-split objective f_i, i = 0..254 (exposed for tests).
std::array<double, 255> GhtObjective(const Histogram256& histogram, const GhtOptions& options = {});

// matplotlib `gray_r` byte of colormap index i: trunc(255·(1 − i·(1/255))) in double precision.
const std::array<std::uint8_t, 256>& GrayReversedLut();

// Which missing depths set |Δ| to 0 (METRICS.md §4 step 1).
//  kBefore (default): only pixels without depth before, as the released evaluator does (its test for
//    "no depth after" compares against a negated uint8 array that wraps, so it never fires). A pixel
//    with depth before and none after keeps |Δ| = D1: a removed object with nothing behind it left
//    no depth, which is a change.
//  kBoth: pixels without depth on either side (al-refine before issue 16; a patched evaluator).
enum class DepthHoles { kBefore, kBoth };
const char* DepthHolesName(DepthHoles holes);
// "before" / "both"; nullopt for anything else.
std::optional<DepthHoles> DepthHolesFromName(const std::string& name);

// Result of a depth-change detection, in either mode.
struct DepthChange {
  Mask changed;              // the thresholded change mask (all false when constant)
  Gray8 image;               // 8-bit: the inverted byte image; float: the bin image b (0 = no change)
  // Per pixel, the change on the stretched scale before quantisation: 256·(a − min)/(max − min) in
  // 8-bit mode, 256·Δ/R in float mode (256 = the largest change; 0 = none). Read by the trust flags.
  std::vector<float> level;
  double threshold = 0;      // GHT t
  bool constant = false;     // the raw `changed` was all true or all false (8-bit mode → no change)
  std::size_t valid_pixels = 0;  // pixels where both depths are valid
  std::size_t holes_before = 0;  // pixels without depth before (|Δ| = 0 in either rule)
  std::size_t holes_after = 0;   // pixels with depth before and none after
};

// 8-bit mode. D1 = before, D2 = after, same size (throws al::Error otherwise); 0 = no depth.
DepthChange DepthChange8Bit(const Gray8& before, const Gray8& after, const GhtOptions& options = {},
                            DepthHoles holes = DepthHoles::kBefore);

// Float renders: expected depth and alpha per pixel (alpha may be empty: then every finite depth
// > 0 is a hit).
struct DepthRender {
  int width = 0, height = 0;
  std::vector<float> depth, alpha;
};
enum class DepthNorm { kMaxDiff, kRange };
const char* DepthNormName(DepthNorm norm);
struct FloatDepthOptions {
  DepthNorm depth_norm = DepthNorm::kMaxDiff;  // normaliser R of METRICS.md §5 step 2
  float alpha_hit = 0.0f;                      // a pixel is a hit iff alpha > alpha_hit
  // kBefore: a pixel hit before and empty after is a change at the top bin (255), so it always
  // counts as changed; kBoth: it is ignored like a pixel empty before.
  DepthHoles holes = DepthHoles::kBefore;
  GhtOptions ght;
  void Check() const;  // alpha_hit in [0, 1), and the GHT options
};
std::vector<std::uint8_t> HitMask(const DepthRender& render, float alpha_hit);
DepthChange DepthChangeFloat(const DepthRender& before, const DepthRender& after, const FloatDepthOptions& options = {});

// METRICS.md §6: the published-pipeline 8-bit depth pair from float renders (joint scale).
struct Depth8Pair {
  Gray8 before, after;
  double zmin = 0, zmax = 0;
  std::size_t hits_before = 0, hits_after = 0;
};
Depth8Pair DepthTo8Bit(const DepthRender& before, const DepthRender& after, float alpha_hit = 0.0f);

// Score (METRICS.md §4 step 6): object = masks/X.png > 0, nullptr = missing (empty, still counts).
// `changed` is resized to the object's size with the "exact" rule.
struct DepthScore {
  double acc_delta_depth = 0, iou = 0;
  double collateral_depth = 0;  // |changed ∩ Ō| / |Ō| (§7), 0 if Ō empty
  bool missing_object = false;
};
DepthScore ScoreDepthChange(const Mask* object, const Mask& changed);

// Trust flags of one view (depth_trust.hpp). `object` as in ScoreDepthChange (nullptr = missing,
// which raises small_object); the change is resized to the object's size with the "exact" rule.
DepthTrust AssessDepthTrust(const Mask* object, const DepthChange& change, const DepthTrustOptions& options = {});

// Per-image record of depth.json.
struct DepthRecord {
  std::string image;
  DepthScore score;
  double threshold = 0;
  bool constant = false;
  DepthTrust trust;
  std::size_t holes_before = 0, holes_after = 0;
};
// Per-scene mean/std over the records given (pooled: pass the records of all scenes).
struct DepthSummary {
  MeanStd acc_delta_depth, iou, collateral_depth;
  MeanStd acc_delta_depth_trusted;  // over the images without a trust flag
  std::size_t images = 0, constant_masks = 0, missing_object = 0;
  std::size_t holes_before = 0, holes_after = 0;  // pixels, summed over the images
  std::vector<std::pair<std::string, std::vector<std::string>>> flagged;  // (image, flags), in record order
  // Means, counts, flag counts and the flagged records; `unit` names the records ("image" in
  // `metrics --dir`, "view" in eval): trust.flagged_images / flagged_views, flagged[].image / .view.
  nlohmann::json ToJson(const std::string& unit = "image") const;
};
DepthSummary SummarizeDepth(const std::vector<DepthRecord>& records);

}  // namespace al::metrics
