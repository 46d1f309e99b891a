// Method presets (al/refine/preset.hpp).
#include "al/refine/preset.hpp"

#include "al/core/error.hpp"

namespace al {

MethodPreset MethodPresetFor(const std::string& method) {
  if (method == "fgs") return {.features = "semantic_", .wide_credit = true, .centre = Centring::kShared};
  if (method == "gg")
    return {.features = "obj_dc_,auto", .subset_ply_is = RemovedIs::kRemaining, .prior_weight = 0.55,
            .bk_lambda = 1.5};
  // SAGS has no features of its own: the scene's semantic ones when present (FORMATS.md §5.3).
  if (method == "sags")
    return {.features = "auto", .prototype_credit = true, .prior_weight = 0.55, .feature_width = 2.0};
  if (method == "gc") return {.features = "colour", .gc_polarity = true, .restore = false};
  if (method == "generic") return {};
  throw Error("--method: unknown '" + method + "' (fgs, gg, sags, gc, generic)", ExitCode::kUsage);
}

double MethodPreset::LambdaFor(const std::string& solver) const { return solver == "bk" ? bk_lambda : 1.0; }

nlohmann::json MethodPreset::ToJson() const {
  return {{"features", features},
          {"subset_ply_is", subset_ply_is == RemovedIs::kRemaining ? "remaining" : "removed"},
          {"gc_polarity", gc_polarity},
          {"prototype_credit", prototype_credit},
          {"wide_credit", wide_credit},
          {"centre", centre == Centring::kShared ? "shared" : "on"},
          {"restore", restore},
          {"prior_weight", prior_weight},
          {"bk_lambda", bk_lambda},
          {"feature_width", feature_width}};
}

}  // namespace al
