// The flags of the feature metrics (`eval`), declared once: which features, how they are segmented
// and where the target prototype comes from when no labels are given (FGS prompts).
#pragma once
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "al/eval/feature_eval.hpp"
#include "al/scene/scene.hpp"

namespace al::cli {

struct FeatureFlags {
  std::string mode = "auto", centre = "on", prototype = "auto", prompts, decoder;
  std::vector<int> positives;
  double fgs_threshold = 0.4;
  eval::FeatureEvalOptions options;
};

// --feature-metrics --feature-min-sim --feature-channels --feature-centre --feature-k --feature-prototype
// --prompt-embeddings --positive --fgs-threshold --decoder
void AddFeatureFlags(CLI::App& app, FeatureFlags& flags);

// The parsed flags as options. Applies --decoder to scene.features and, with prompts, derives the
// prototype set by FGS's rule (al/refine/fgs_mask.hpp). Throws al::Error on bad input.
eval::FeatureEvalOptions ToFeatureOptions(const FeatureFlags& flags, Scene& scene);

}  // namespace al::cli
