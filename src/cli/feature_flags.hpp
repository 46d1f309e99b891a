// The flags of the feature metrics (`eval`): the options come from their tables
// (FeatureEvalOptions, FeatureFieldOptions, FeatureSegOptions: --feature-*), the inputs that pick the
// target prototype without labels (FGS prompts) and an optional feature decoder are declared here.
#pragma once
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "al/eval/feature_eval.hpp"
#include "al/scene/scene.hpp"

namespace al::cli {

struct FeatureFlags {
  std::string prompts, decoder;
  std::vector<int> positives;
  double fgs_threshold = 0.4;
  eval::FeatureEvalOptions options;
};

// --feature-* (from the tables), --prompt-embeddings --positive --fgs-threshold --decoder
void AddFeatureFlags(CLI::App& app, FeatureFlags& flags);

// The parsed flags as options (checked). Applies --decoder to scene.features and, with prompts,
// derives the prototype set by FGS's rule (al/refine/fgs_mask.hpp). Throws al::Error on bad input.
eval::FeatureEvalOptions ToFeatureOptions(const FeatureFlags& flags, Scene& scene);

}  // namespace al::cli
