// Scene statistics for `al-refine info` and the demo (finite values only).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "al/io/ply.hpp"

namespace al {
namespace {

// min, median (lower middle), max, mean of v; zeros when empty.
void Stats(std::vector<double> v, double& mn, double& med, double& mx, double& mean) {
  mn = med = mx = mean = 0;
  if (v.empty()) return;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>((v.size() - 1) / 2);
  std::nth_element(v.begin(), mid, v.end());
  med = *mid;
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  mn = *lo;
  mx = *hi;
  double sum = 0;
  for (double x : v) sum += x;
  mean = sum / static_cast<double>(v.size());
}

}  // namespace

SceneSummary SummarizeScene(const Scene& scene) {
  SceneSummary s;
  s.num_gaussians = scene.size();
  s.sh_degree = scene.sh_degree;
  s.feature_dim = static_cast<std::size_t>(scene.features.cols());
  s.feature_prefix = s.feature_dim ? scene.feature_prefix : "";
  s.source_format = scene.source_format;
  s.nonfinite = CountNonFinite(scene);
  bool any = false;
  std::vector<double> scales, opacities;
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(scene.size()); ++i) {
    const auto m = scene.means.row(i);
    if (m.allFinite()) {
      for (int c = 0; c < 3; ++c) {
        s.bbox_min[c] = any ? std::min(s.bbox_min[c], m(c)) : m(c);
        s.bbox_max[c] = any ? std::max(s.bbox_max[c], m(c)) : m(c);
      }
      any = true;
    }
    if (scene.has_scales && scene.log_scales.row(i).allFinite())
      scales.push_back(std::exp(static_cast<double>(scene.log_scales.row(i).maxCoeff())));
    if (scene.has_opacity && std::isfinite(scene.opacity_logits(i)))
      opacities.push_back(1.0 / (1.0 + std::exp(-static_cast<double>(scene.opacity_logits(i)))));
  }
  Stats(std::move(scales), s.scale_min, s.scale_median, s.scale_max, s.scale_mean);
  Stats(std::move(opacities), s.opacity_min, s.opacity_median, s.opacity_max, s.opacity_mean);
  return s;
}

nlohmann::json SummaryToJson(const SceneSummary& s) {
  const auto& nf = s.nonfinite;
  return {{"num_gaussians", s.num_gaussians},
          {"sh_degree", s.sh_degree},
          {"feature_dim", s.feature_dim},
          {"feature_prefix", s.feature_prefix},
          {"source_format", s.source_format},
          {"bbox_min", {s.bbox_min[0], s.bbox_min[1], s.bbox_min[2]}},
          {"bbox_max", {s.bbox_max[0], s.bbox_max[1], s.bbox_max[2]}},
          {"scale_stats", {{"min", s.scale_min}, {"median", s.scale_median}, {"max", s.scale_max}, {"mean", s.scale_mean}}},
          {"opacity_stats",
           {{"min", s.opacity_min}, {"median", s.opacity_median}, {"max", s.opacity_max}, {"mean", s.opacity_mean}}},
          {"nonfinite",
           {{"means", nf.means}, {"scales", nf.scales}, {"rotations", nf.rotations}, {"opacities", nf.opacities},
            {"sh", nf.sh}, {"features", nf.features}, {"gaussians_with_any", nf.gaussians_with_any}}}};
}

std::string SummaryToText(const SceneSummary& s) {
  std::ostringstream o;
  o << "Gaussians:      " << s.num_gaussians << " (" << s.source_format << ")\n"
    << "SH degree:      " << s.sh_degree << "\n"
    << "features:       " << (s.feature_dim ? std::to_string(s.feature_dim) + " (" + s.feature_prefix + "*)" : "none")
    << "\n"
    << "bbox min:       " << s.bbox_min[0] << " " << s.bbox_min[1] << " " << s.bbox_min[2] << "\n"
    << "bbox max:       " << s.bbox_max[0] << " " << s.bbox_max[1] << " " << s.bbox_max[2] << "\n"
    << "max scale:      min " << s.scale_min << "  median " << s.scale_median << "  max " << s.scale_max << "\n"
    << "opacity:        min " << s.opacity_min << "  median " << s.opacity_median << "  max " << s.opacity_max << "\n"
    << "non-finite:     " << s.nonfinite.gaussians_with_any << " Gaussians (means " << s.nonfinite.means << ", scales "
    << s.nonfinite.scales << ", rotations " << s.nonfinite.rotations << ", opacities " << s.nonfinite.opacities
    << ", sh " << s.nonfinite.sh << ", features " << s.nonfinite.features << ")\n";
  return o.str();
}

std::vector<std::string> MissingRenderColumns(const Scene& scene) {
  if (scene.size() == 0) return {};
  const std::string file = scene.source_path.empty() ? std::string("scene") : scene.source_path;
  std::vector<std::string> w;
  auto missing = [&](bool has, const char* props, const char* fallback) {
    if (!has) w.push_back(file + ": no " + props + " properties: " + fallback);
  };
  missing(scene.has_opacity, "'opacity'", "every Gaussian is rendered at opacity sigmoid(0) = 0.5");
  missing(scene.has_rotations, "'rot_0'..'rot_3'", "every Gaussian is rendered unrotated (identity quaternion)");
  missing(scene.has_f_dc, "'f_dc_0'..'f_dc_2'", "every Gaussian is rendered grey (SH DC 0)");
  missing(scene.has_scales, "'scale_0'..'scale_2'", "every Gaussian is rendered with unit scales (log-scale 0)");
  return w;
}

}  // namespace al
