// The per-Gaussian values a feature render composites (RenderOptions::features), prepared once
// per scene from its semantic features (N x D, any D >= 1):
//  1. each row is normalised to unit length (a zero or non-finite row becomes 0: "no feature",
//     it still occludes through its opacity but adds nothing to the feature sum);
//  2. optionally centred by the scene mean of the unit rows. Distilled CLIP-like features share a
//     strong common component (median pairwise cosine ~0.75 in real scenes), so raw cosines between
//     unrelated classes are high; after centring, cosines compare what tells classes apart.
//     Compositing is linear, so the rendered centred feature is the rendered unit feature minus
//     the mean (up to the per-pixel normalisation);
//  3. when D exceeds max_channels, projected on the leading max_channels principal axes of the
//     (centred) unit rows: a render composites at most kMaxFeatureChannels floats per pixel, and the
//     projection keeps the directions along which the scene's features vary most (kept_variance
//     says how much). Cosines in the projected space approximate those of the full space.
// Deterministic and independent of the thread count.
#pragma once
#include <cstddef>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "al/core/option_table.hpp"
#include "al/render/render.hpp"

namespace al {

struct FeatureFieldOptions {
  bool centre = true;                       // subtract the scene mean of the unit features
  int max_channels = kMaxFeatureChannels;   // 1..kMaxFeatureChannels; wider features are projected (PCA)
  int pca_rows = 65536;                     // rows (evenly spaced) the covariance is estimated from
  int num_threads = 0;                      // 0 = OpenMP default; results do not depend on it (no table row)
  static const OptionTable<FeatureFieldOptions>& Table();  // feature_centre, feature_channels, feature_pca_rows
  void Check() const;                       // al::Error (usage) on an out-of-range value
};

struct FeatureField {
  RowMatXf channels;           // N x d: what the renderer composites (d <= max_channels)
  Eigen::VectorXf mean;        // D: the mean unit feature that was subtracted (zeros if not centred)
  Eigen::MatrixXf basis;       // D x d orthonormal principal axes; empty when not projected (d = D)
  int input_dim = 0;           // D
  bool centred = false;
  double kept_variance = 1.0;  // share of the centred unit features' variance the d channels keep
  std::size_t zero_norm = 0;   // rows with zero or non-finite norm (rendered as "no feature")
  double seconds = 0;
  int dim() const { return static_cast<int>(channels.cols()); }
  bool projected() const { return basis.size() > 0; }
  nlohmann::json ToJson() const;  // {input_dim, channels, centred, projection, kept_variance, zero_norm, seconds}
};

// Throws al::Error when features is empty (no rows or no columns).
FeatureField PrepareFeatureField(const RowMatXf& features, const FeatureFieldOptions& options = {});

}  // namespace al
