// sim_SAM: similarity of two SAM segment sets restricted to the object (METRICS.md §3).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "al/metrics/mask.hpp"

namespace al::metrics {

struct SimSamOptions {
  double min_object_iou = 0.10;        // keep a segment iff IoU(segment, O) >= this (inclusive)
  std::uint8_t object_threshold = 128;  // object mask = luma > this
  void Check() const;  // min_object_iou in [0, 1]
};

struct SimSamMatch {
  int gt_idx = 0, sam_idx = 0;  // indices into the filtered lists
  double iou = 0;
};

struct SimSamResult {
  bool scored = false;  // false: a filtered side is empty (dropped image, excluded from the means)
  int n_gt = 0, n_sam = 0;  // N, M after filtering
  double sim_sam = 0;       // Σ matched IoU / max(N, M)
  std::vector<SimSamMatch> matches;  // only pairs with IoU > 0, in side-A order
};

// side_a ("gt" in the released JSON) and side_b ("sam"): segments of any size, binarised != 0,
// resized to the object mask's size with the floor rule.
SimSamResult ComputeSimSam(const Gray8& object, const std::vector<Mask>& side_a, const std::vector<Mask>& side_b,
                           const SimSamOptions& options = {});

// The filter step alone (exposed for tests and reports): indices of kept segments.
std::vector<int> FilterSegments(const Mask& object, const std::vector<Mask>& segments, const SimSamOptions& options,
                                std::vector<Mask>* kept = nullptr);

}  // namespace al::metrics
