// The graph's options table (al/core/option_table.hpp): one row per user-settable field.
#include "al/core/error.hpp"
#include "al/graph/graph.hpp"

namespace al {
namespace {

const std::vector<std::pair<std::string, PriorSwitch>> kPriorSwitchNames = {
    {"auto", PriorSwitch::kAuto}, {"on", PriorSwitch::kOn}, {"off", PriorSwitch::kOff}};

// A field that is "auto" or a number in range. slot(o) is the optional it lives in (a generic
// lambda, so it serves const and mutable options alike); unset = auto, resolved by the refine
// stages from the --method preset, direct_default for a direct caller.
template <typename Slot>
OptionField<GraphOptions> AutoRealField(const std::string& name, const NumericRange& range, std::string help,
                                        Slot slot, double direct_default) {
  // The range as --help and the out-of-range error spell it ("... = 1.5 must be auto|[0, 1]").
  OptionField<GraphOptions> f{name, OptionType::kText, "auto|" + range.Text(), std::move(help), false, {}, {}, {}};
  f.get = [slot](const GraphOptions& o) {
    const std::optional<double>& v = slot(o);
    return v ? nlohmann::json(*v) : nlohmann::json("auto");
  };
  f.set = [slot, name, range](GraphOptions& o, const nlohmann::json& v) {
    const std::string text = v.get<std::string>();
    if (text == "auto") return void(slot(o).reset());
    slot(o) = ParseOptionText(OptionType::kReal, text, "graph option '" + name + "' (auto|" + range.Text() + ")")
                  .get<double>();
  };
  f.in_range = [slot, range, direct_default](const GraphOptions& o) {
    return range.Contains(slot(o).value_or(direct_default));
  };
  return f;
}

OptionField<GraphOptions> LambdaField() {
  return AutoRealField(
      "lambda", NumericRange::AtLeast(0),
      "edge weight scale (auto: 1.5 for --method gg with solver bk, else 1)",
      [](auto& o) -> auto& { return o.lambda; }, 1.0);
}

OptionField<GraphOptions> PriorWeightField() {
  return AutoRealField("prior_weight", NumericRange::Closed(0, 1),
                       "feature prior in the unary: y = (1 - w) mask + w q, w in [0, 1] (0 = the mask "
                       "alone; auto: 0.55 for --method gg and sags, else 0.5)",
                       [](auto& o) -> auto& { return o.prior.weight; }, 0.5);
}

OptionField<GraphOptions> FeatureWidthField() {
  return AutoRealField("feature_width", NumericRange::Above(0),
                       "feature kernel exp(-d_f^2 / sigma_f^2) with sigma_f = this x the gate bound; the gate "
                       "is unchanged (auto: 2 for --method sags, else 1)",
                       [](auto& o) -> auto& { return o.feature_width; }, 1.0);
}

}  // namespace

const OptionTable<GraphOptions>& GraphOptions::Table() {
  using O = GraphOptions;
  using R = NumericRange;
  static const auto table =
      OptionTable<O>("graph")
          .Int("k", &O::k, R::Closed(1, 1000), "neighbours per node")
          .Real("delta", &O::delta, R::AtLeast(-1),
                "semantic gate: a distance >= 0 of unit features, or in cosine mode a cosine in [-1, 1]")
          .Choice("delta_mode", &O::delta_mode, {{"distance", DeltaMode::kDistance}, {"cosine", DeltaMode::kCosine}},
                  "distance: delta bounds |f_u - f_v|; cosine: delta is a cosine threshold")
          .Custom(LambdaField())
          .Custom(FeatureWidthField())
          .Flag("spatial", &O::spatial, "spatial weight factor exp(-d_x^2 / sigma_x^2)")
          .Int("hops", &O::hops, R::Closed(0, 100), "candidate growth repetitions")
          .Real("radius_scale", &O::radius_scale, R::Above(0), "multiplier of r_i = max exp(scale)")
          .Int("knn_checks", &O::knn_checks, R::AtLeast(0), "0 = exact kNN; > 0 approximate (FLANN checks)")
          .Real("kl_smoothing", &O::kl_smoothing, R::Open(0, 1), "s of the smoothed KL")
          .Int("grow_rounds", &O::grow_rounds, R::Closed(0, 1000),
               "grow the candidate set around what the cut added and solve again, at most this many "
               "times (0 = fixed candidate set)")
          .Choice("centre", &O::centre,
                  {{"auto", Centring::kAuto}, {"on", Centring::kOn}, {"off", Centring::kOff},
                   {"shared", Centring::kShared}},
                  "centre semantic features on the scene mean; shared = only when they share a strong "
                  "common component (CLIP-like: |mean unit feature| >= 0.7); auto: shared for --method fgs, "
                  "else on")
          .Custom(PriorWeightField())
          .Choice("prototype_credit", &O::prior, &PriorOptions::prototype_credit, kPriorSwitchNames,
                  "credit kept Gaussians close to the removed set's mean feature (auto: on for --method sags "
                  "only)")
          .Choice("wide_credit", &O::prior, &PriorOptions::wide_credit, kPriorSwitchNames,
                  "credit kept Gaussians half-way down to the kept ones' projection, for a tight object (auto: "
                  "on for --method fgs only)")
          .Choice("second_object_guard", &O::prior, &PriorOptions::second_object_guard, kPriorSwitchNames,
                  "when the removed set holds a second object (a separate part with >= 20 % of it and "
                  "different features), credit no kept Gaussian: either object may be the target (auto: on)")
          .Choice("taken_whole_guard", &O::taken_whole_guard, kPriorSwitchNames,
                  "a restored Gaussian stays removed when its feature region (the scene's Gaussians linked to "
                  "it through the gate) is one the method took whole: >= 40 % of it removed, holding >= 2 % "
                  "but less than half of the removed set, e.g. an object's part with off features; not when "
                  "the removed set holds a second object (auto: on)")
          .Choice("restore_window", &O::restore_window, kPriorSwitchNames,
                  "a restored Gaussian stays removed when its cosine to the removed set's mean centred feature "
                  "lies within --restore-window-mads robust standard deviations below the removed median: the "
                  "cut's restores of the object's own rows; not when the removed set holds a second object "
                  "(auto: off; docs/refine.md item 15)")
          .Real("restore_window_mads", &O::restore_window_mads, R::Closed(0, 100),
                "the window's depth in robust standard deviations (1.4826 x the median absolute deviation)")
          .Real("second_object_tolerance", &O::second_object_tolerance, R::Closed(0, 1),
                "when the removed set holds a second object, additions that complete one of the two stop "
                "where F1 against the other (read as the target) could fall by more than this; farthest "
                "first (1 = never)")
          .Choice("feature_group_bound", &O::feature_group_bound, kPriorSwitchNames,
                  "when the removed set holds an object taken whole beside a group of other features taken "
                  "in part (with the prototype credit: sags), the additions that complete one of the two stop "
                  "where F1 read with the other as the object could fall by more than --feature-group-tolerance; "
                  "auto: only where the additions are a layer of a body that goes on beyond them (a "
                  "neighbour), not where they complete a part (the object's own off-feature part)")
          .Real("feature_group_tolerance", &O::feature_group_tolerance, R::Closed(0, 1),
                "the F1 that bound allows either reading to lose (1 = never take back; the report and a "
                "warning give the F1 at stake)");
  return table;
}

void GraphOptions::Check() const {
  Table().Check(*this);
  const bool cosine = delta_mode == DeltaMode::kCosine;
  if (cosine ? delta > 1.0 : delta < 0.0)
    throw Error("graph option 'delta' = " + FormatOptionNumber(delta) + " must be " +
                    (cosine ? "in [-1, 1] in cosine mode" : ">= 0 in distance mode"),
                ExitCode::kUsage);
}

}  // namespace al
