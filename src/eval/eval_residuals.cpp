// The evaluator's residuals (al/eval/residuals.hpp).
#include "al/eval/residuals.hpp"

namespace al::eval {
namespace {

using json = nlohmann::json;

metrics::ViewResidual Residual(const RenderOutput& before, const RenderOutput& after, const RenderOutput& ideal,
                               const metrics::ResidualOptions& o, std::vector<float>* share) {
  return metrics::ComputeResidual({before.width, before.height, before.rgb, after.rgb, ideal.rgb}, o, share);
}

metrics::PixelRender PixelsOf(const RenderOutput& r) { return {r.rgb, r.depth, r.alpha}; }

// The residual_px "share" of the overlay: 1 where the mask pixel is still there, 0 where it changed.
void ShareFromStill(const metrics::Mask& object, const metrics::Mask& still, std::vector<float>& share) {
  share.assign(object.bits.size(), -1.0f);
  for (std::size_t p = 0; p < object.bits.size(); ++p)
    if (object.bits[p]) share[p] = still.bits[p] ? 1.0f : 0.0f;
}

using ResidualField = std::optional<metrics::ViewResidual> ColumnViewMetrics::*;
using SummaryField = std::optional<metrics::ResidualSummary> ColumnSummary::*;
struct Kind {
  const char* name;
  ResidualField view;
  SummaryField summary;
};
constexpr Kind kKinds[] = {{"residual_gt", &ColumnViewMetrics::residual_gt, &ColumnSummary::residual_gt},
                           {"residual_est", &ColumnViewMetrics::residual_est, &ColumnSummary::residual_est},
                           {"residual_px", &ColumnViewMetrics::residual_px, &ColumnSummary::residual_px}};

}  // namespace

std::string HeadlineResidual(bool has_labels, std::size_t num_columns) {
  if (has_labels) return "residual_gt";
  return num_columns > 1 ? "residual_est" : "residual_px";
}

void ScoreResiduals(const ResidualInput& in, const metrics::ResidualOptions& o, const std::string& headline,
                    ColumnViewMetrics& m, std::vector<float>& share) {
  share.clear();
  if (in.ideal_gt) m.residual_gt = Residual(in.before, in.after, *in.ideal_gt, o, headline == "residual_gt" ? &share : nullptr);
  if (in.ideal_est)
    m.residual_est = Residual(in.before, in.after, *in.ideal_est, o, headline == "residual_est" ? &share : nullptr);
  metrics::Mask still;
  m.residual_px = metrics::ComputePixelResidual(PixelsOf(in.before), PixelsOf(in.after), in.object, o, &still);
  // The column that is residual_est's ideal has no residual_est: its overlay shows residual_px.
  if (share.empty()) ShareFromStill(in.object, still, share);
}

void SummarizeResiduals(const std::vector<ViewRecord>& views, std::size_t c, ColumnSummary& s) {
  for (const Kind& kind : kKinds) {
    std::vector<metrics::ViewResidual> values;
    for (const ViewRecord& v : views)
      if (c < v.columns.size() && (v.columns[c].*kind.view)) values.push_back(*(v.columns[c].*kind.view));
    if (!values.empty()) s.*kind.summary = metrics::SummarizeResidual(values);
  }
}

void AddResidualJson(const std::vector<ViewRecord>& views, std::size_t c, const ColumnSummary& s, json& out) {
  for (const Kind& kind : kKinds) {
    const auto& summary = s.*kind.summary;
    if (!summary) continue;
    json per_view = json::array();
    for (const ViewRecord& v : views) {
      if (c >= v.columns.size() || !(v.columns[c].*kind.view)) continue;
      const metrics::ViewResidual& r = *(v.columns[c].*kind.view);
      per_view.push_back({{"view", v.name}, {"residual", r.value ? json(*r.value) : json(nullptr)}, {"pixels", r.pixels}});
    }
    const bool scored = summary->stats.count > 0;
    out[kind.name] = {{"mean", scored ? json(summary->stats.mean) : json(nullptr)},
                      {"std", scored ? json(summary->stats.std) : json(nullptr)},
                      {"views", summary->stats.count},
                      {"views_not_scored", summary->small_views},
                      {"per_view", std::move(per_view)}};
  }
}

json ResidualsInfoJson(const std::string& headline, const std::vector<EvalColumn>& columns, bool has_labels,
                       const metrics::ResidualOptions& o) {
  const std::string footprint = "O = pixels where |rgb_before - rgb_ideal| > " + FormatOptionNumber(o.footprint) +
                                " (Euclidean, RGB in [0, 1]); per view the mean over O of min(1, |rgb_after - "
                                "rgb_ideal| / |rgb_before - rgb_ideal|); mean over the views with |O| >= " +
                                std::to_string(o.min_pixels) + "; 0 = gone, 1 = untouched";
  json info = {{"headline", headline},
               {"residual_gt", {{"ideal", has_labels ? json("the scene without the labels' target") : json(nullptr)},
                                {"definition", footprint}}},
               {"residual_est",
                {{"ideal", columns.size() > 1 ? json("the render of refinement '" + columns[1].label + "'") : json(nullptr)},
                 {"ideal_column", columns.size() > 1 ? json(columns[1].name) : json(nullptr)},
                 {"definition", footprint}}},
               {"residual_px",
                {{"definition", "share of the object mask whose colour moved by at most " +
                                    FormatOptionNumber(o.colour_tol) + " and depth by at most " +
                                    FormatOptionNumber(o.depth_tol) + " of the depth before (hit/empty unchanged); "
                                    "views with a mask of at least " + std::to_string(o.min_pixels) + " pixels"}}}};
  return info;
}

}  // namespace al::eval
