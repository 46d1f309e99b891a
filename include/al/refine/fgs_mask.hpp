// FGS's deletion rule recomputed from the scene's features (FORMATS.md §5.1): per Gaussian
// s_k = <f/||f||, t_k>, P = softmax(s) (no temperature); removed iff argmax_k s_k is a positive
// prompt OR sum_{k in positives} P_k >= threshold. Optional per-Gaussian decoder f' = W f + b.
#pragma once
#include <string>
#include <vector>

#include "al/scene/scene.hpp"

namespace al {

struct FgsMaskOptions {
  std::vector<int> positives;  // prompt rows that name the object (at least one)
  double threshold = 0.4;      // paper value; official configs use 0.198 / 0.24
  void Check() const;  // at least one positive prompt row >= 0, threshold in [0, 1]
};

struct FgsMaskResult {
  std::vector<bool> removed;          // N
  std::size_t num_removed = 0;
  std::size_t by_argmax = 0;          // removed because the argmax is positive
  std::size_t by_threshold_only = 0;  // removed by the positive share alone
  std::size_t near_threshold = 0;     // |sum P_pos − threshold| <= 1e-3 (float16 upstream may flip)
  std::size_t zero_norm = 0;          // features of zero norm (never removed)
};

// features: N×D; prompts: T×D (rows = prompts). Throws al::Error on shape mismatches or bad
// positive indices.
FgsMaskResult FgsDerivedMask(Eigen::Ref<const RowMatXf> features, const RowMatXf& prompts,
                             const FgsMaskOptions& options);

// Reads W (.npy, (D',D) or (D',D,1,1)) and b ((D',)) and returns features·Wᵀ + b (N×D').
RowMatXf ApplyDecoder(Eigen::Ref<const RowMatXf> features, const std::string& weight_npy, const std::string& bias_npy);

// Reads a float .npy of shape (R, C) as a row-major matrix (name used in errors).
RowMatXf ReadMatrixNpy(const std::string& path);

}  // namespace al
