#include "src/cli/feature_flags.hpp"

#include "al/core/error.hpp"
#include "al/refine/fgs_mask.hpp"

namespace al::cli {

void AddFeatureFlags(CLI::App& app, FeatureFlags& f) {
  eval::FeatureEvalOptions& o = f.options;
  app.add_option("--feature-metrics", f.mode, "Feature metrics (IoU_drop_feat, acc_seg_feat, residual_feat): auto "
                 "(when the scene has semantic features) | on | off")
      ->check(CLI::IsMember({"auto", "on", "off"}))->capture_default_str();
  app.add_option("--feature-min-sim", o.segmentation.min_similarity,
                 "A pixel is the target only at cosine >= this to its prototype (centred features)")
      ->check(CLI::Range(-1.0, 1.0))->capture_default_str();
  app.add_option("--feature-channels", o.field.max_channels, "Rendered feature channels; wider features are "
                 "projected on their principal axes")
      ->check(CLI::Range(1, kMaxFeatureChannels))->capture_default_str();
  app.add_option("--feature-centre", f.centre, "Subtract the scene's mean unit feature before cosines: on | off")
      ->check(CLI::IsMember({"on", "off"}))->capture_default_str();
  app.add_option("--feature-k", o.kmeans_k, "Without --labels: k-means clusters of the kept candidates that "
                 "compete with the target")
      ->check(CLI::Range(1, 256))->capture_default_str();
  app.add_option("--feature-prototype", f.prototype, "Target prototype: auto (the --labels object, else the "
                 "--positive prompts' Gaussians, else the removed set) | removal (ignore --labels here)")
      ->check(CLI::IsMember({"auto", "removal"}))->capture_default_str();
  app.add_option("--prompt-embeddings", f.prompts, "FGS text embeddings T.npy: with --positive, the target "
                 "prototype is the mean feature of the Gaussians FGS's rule selects");
  app.add_option("--positive", f.positives, "Positive prompt rows")->delimiter(',');
  app.add_option("--fgs-threshold", f.fgs_threshold, "FGS deletion threshold for --positive")->capture_default_str();
  app.add_option("--decoder", f.decoder, "W.npy,b.npy: per-Gaussian f' = W f + b before everything else");
}

eval::FeatureEvalOptions ToFeatureOptions(const FeatureFlags& f, Scene& scene) {
  eval::FeatureEvalOptions o = f.options;
  using Mode = eval::FeatureEvalOptions::Mode;
  o.mode = f.mode == "on" ? Mode::kOn : f.mode == "off" ? Mode::kOff : Mode::kAuto;
  o.field.centre = f.centre == "on";
  o.use_labels = f.prototype == "auto";
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
