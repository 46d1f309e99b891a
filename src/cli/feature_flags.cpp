#include "src/cli/feature_flags.hpp"

#include "al/core/error.hpp"
#include "al/refine/fgs_mask.hpp"
#include "src/cli/option_flags.hpp"

namespace al::cli {

void AddFeatureFlags(CLI::App& app, FeatureFlags& f) {
  const std::string group = "Feature metrics";
  AddOptionFlags(app, eval::FeatureEvalOptions::Table(), f.options, group);
  AddOptionFlags(app, FeatureFieldOptions::Table(), f.options.field, group, {"feature_pca_rows"});
  AddOptionFlags(app, metrics::FeatureSegOptions::Table(), f.options.segmentation, group);
  app.add_option("--prompt-embeddings", f.prompts, "FGS text embeddings T.npy: with --positive, the target "
                 "prototype is the mean feature of the Gaussians FGS's rule selects")->group(group);
  app.add_option("--positive", f.positives, "Positive prompt rows")->delimiter(',')->group(group);
  app.add_option("--fgs-threshold", f.fgs_threshold, "FGS deletion threshold for --positive")
      ->capture_default_str()->group(group);
  app.add_option("--decoder", f.decoder, "W.npy,b.npy: per-Gaussian f' = W f + b before everything else")
      ->group(group);
}

eval::FeatureEvalOptions ToFeatureOptions(const FeatureFlags& f, Scene& scene) {
  eval::FeatureEvalOptions o = f.options;
  if (!f.decoder.empty()) {
    const auto comma = f.decoder.find(',');
    if (comma == std::string::npos) throw Error("--decoder: expected W.npy,b.npy", ExitCode::kUsage);
    if (scene.features.cols() == 0) throw Error("--decoder needs semantic features in the scene", ExitCode::kUsage);
    scene.features = ApplyDecoder(scene.features, f.decoder.substr(0, comma), f.decoder.substr(comma + 1));
  }
  if (f.prompts.empty() != f.positives.empty())
    throw Error("--prompt-embeddings and --positive go together", ExitCode::kUsage);
  if (!f.prompts.empty()) {
    if (scene.features.cols() == 0) throw Error("--prompt-embeddings needs semantic features", ExitCode::kUsage);
    FgsMaskOptions fo;
    fo.positives = f.positives;
    fo.threshold = f.fgs_threshold;
    o.target_set = FgsDerivedMask(scene.features, ReadMatrixNpy(f.prompts), fo).removed;
    std::string rows;
    for (int p : f.positives) rows += (rows.empty() ? "" : ",") + std::to_string(p);
    o.target_set_source = "prompts " + rows + " of " + f.prompts;
  }
  o.Check();
  return o;
}

}  // namespace al::cli
