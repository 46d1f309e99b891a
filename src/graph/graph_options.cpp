// The graph's options table (al/core/option_table.hpp): one row per user-settable field.
#include "al/core/error.hpp"
#include "al/graph/graph.hpp"

namespace al {
namespace {

const std::vector<std::pair<std::string, PriorSwitch>> kPriorSwitchNames = {
    {"auto", PriorSwitch::kAuto}, {"on", PriorSwitch::kOn}, {"off", PriorSwitch::kOff}};

// auto or a number in [0, 1] (al/graph/prior.hpp: unset = the preset's weight).
OptionField<GraphOptions> PriorWeightField() {
  const NumericRange range = NumericRange::Closed(0, 1);
  // The range as --help and the out-of-range error spell it ("... = 1.5 must be auto|[0, 1]").
  OptionField<GraphOptions> f{"prior_weight", OptionType::kText, "auto|" + range.Text(),
                              "feature prior in the unary: y = (1 - w) mask + w q, w in [0, 1] (0 = the mask "
                              "alone; auto: 0.55 for --method gg and sags, else 0.5)",
                              false, {}, {}, {}};
  f.get = [](const GraphOptions& o) {
    return o.prior.weight ? nlohmann::json(*o.prior.weight) : nlohmann::json("auto");
  };
  f.set = [](GraphOptions& o, const nlohmann::json& v) {
    const std::string text = v.get<std::string>();
    if (text == "auto") return void(o.prior.weight.reset());
    o.prior.weight = ParseOptionText(OptionType::kReal, text, "graph option 'prior_weight' (auto|[0, 1])")
                         .get<double>();
  };
  f.in_range = [range](const GraphOptions& o) { return range.Contains(o.prior.Weight()); };
  return f;
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
          .Real("lambda", &O::lambda, R::AtLeast(0), "edge weight scale")
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
                  "different features), credit no kept Gaussian: either object may be the target (auto: on)");
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
