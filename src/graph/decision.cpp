// Threshold rules over solver output (see decision.hpp).
#include "al/decision.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <numeric>

#include "al/core/error.hpp"

namespace al {
namespace {

// Share of each node's segment (connected component of the graph) that is in R, weighted by the
// node weights: sum w_v [v in R] / sum w_v over the segment (the mask, not the soft observations
// of the feature prior). Also returns the segment root per node.
std::vector<double> SegmentShares(const RefineProblem& problem, const std::vector<bool>& removed,
                                  std::vector<std::int32_t>& root) {
  const std::size_t V = problem.num_nodes();
  root.resize(V);
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](std::int32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  if (problem.first_edge.size() == V + 1) {
    for (std::size_t u = 0; u < V; ++u)
      for (auto e = problem.first_edge[u]; e < problem.first_edge[u + 1]; ++e) {
        const std::int32_t v = problem.adj_vertices.at(static_cast<std::size_t>(e));
        if (v < 0 || static_cast<std::size_t>(v) >= V)
          throw Error("decision: edge endpoint out of range", ExitCode::kInternal);
        const std::int32_t a = find(static_cast<std::int32_t>(u)), b = find(v);
        if (a != b) root[std::max(a, b)] = std::min(a, b);
      }
  } else if (!problem.first_edge.empty()) {
    throw Error("decision: first_edge has " + std::to_string(problem.first_edge.size()) +
                " entries for " + std::to_string(V) + " nodes", ExitCode::kInternal);
  }
  std::vector<double> in_r(V, 0.0), total(V, 0.0);
  const bool weighted = problem.node_weights.size() == V;
  for (std::size_t v = 0; v < V; ++v) {
    root[v] = find(static_cast<std::int32_t>(v));
    const double w = weighted ? problem.node_weights[v] : 1.0;
    in_r[root[v]] += removed[static_cast<std::size_t>(problem.node_ids[v])] ? w : 0.0;
    total[root[v]] += w;
  }
  std::vector<double> share(V, 0.0);
  for (std::size_t v = 0; v < V; ++v)
    if (total[root[v]] > 0) share[v] = in_r[root[v]] / total[root[v]];
  return share;
}

}  // namespace

std::string DecisionRule::ToString() const {
  if (kind == Kind::kPercentile) return "percentile:" + std::to_string(percentile);
  nlohmann::json j = threshold;
  return j.dump();
}

DecisionRule ParseDecisionRule(const std::string& text) {
  DecisionRule rule;
  const std::string prefix = "percentile:";
  if (text.rfind(prefix, 0) == 0) {
    const std::string num = text.substr(prefix.size());
    int p = -1;
    const auto [ptr, ec] = std::from_chars(num.data(), num.data() + num.size(), p);
    if (ec != std::errc() || ptr != num.data() + num.size() || p < 0 || p > 100)
      throw Error("'" + text + "' is not percentile:P with an integer P in [0, 100]",
                  ExitCode::kUsage);
    rule.kind = DecisionRule::Kind::kPercentile;
    rule.percentile = p;
    return rule;
  }
  std::size_t used = 0;
  double t = 0;
  try {
    t = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(t))
    throw Error("'" + text + "' is not a number (e.g. 0.5) or percentile:P (e.g. percentile:95)",
                ExitCode::kUsage);
  rule.threshold = t;
  return rule;
}

const OptionTable<DecisionOptions>& DecisionOptions::Table() {
  OptionField<DecisionOptions> threshold{"threshold", OptionType::kText, "TAU|percentile:P",
                                         "decision: a number tau in [0, 1], or percentile:P with P in [0, 100] (nearest rank over C)",
                                         false, {}, {}, {}};
  threshold.get = [](const DecisionOptions& o) { return nlohmann::json(o.rule.ToString()); };
  threshold.set = [](DecisionOptions& o, const nlohmann::json& v) {
    try {
      o.rule = ParseDecisionRule(v.get<std::string>());
    } catch (const Error& e) {
      throw Error(std::string("decision option 'threshold': ") + e.what(), ExitCode::kUsage);
    }
  };
  threshold.in_range = [](const DecisionOptions& o) {
    return o.rule.kind == DecisionRule::Kind::kPercentile ? o.rule.percentile >= 0 && o.rule.percentile <= 100
                                                          : o.rule.threshold >= 0.0 && o.rule.threshold <= 1.0;
  };
  static const auto table =
      OptionTable<DecisionOptions>("decision")
          .Custom(std::move(threshold))
          .Choice("restore", &DecisionOptions::restore,
                  {{"auto", Restore::kAuto}, {"on", Restore::kOn}, {"off", Restore::kOff}},
                  "also let removed Gaussians with p < tau return (off = add only; auto: off for --method gc, "
                  "else on)")
          .Real("min_segment_share", &DecisionOptions::min_segment_share, NumericRange::Closed(0, 1),
                "segment rule: add only to graph components the method removed at least this share of "
                "(0 = off, SPEC 5's plain rule)");
  return table;
}

DecisionResult ApplyDecision(const std::vector<bool>& removed, const RefineProblem& problem,
                             const std::vector<double>& p, const DecisionOptions& options) {
  const std::size_t V = problem.num_nodes();
  if (p.size() != V || problem.node_ids.size() != V)
    throw Error("decision: solver output has " + std::to_string(p.size()) + " values for " +
                std::to_string(V) + " nodes", ExitCode::kInternal);
  if (!(options.min_segment_share >= 0.0 && options.min_segment_share <= 1.0))
    throw Error("decision: min_segment_share must be in [0, 1]", ExitCode::kUsage);
  DecisionResult r;
  r.refined = removed;
  r.min_segment_share = options.min_segment_share;
  if (options.rule.kind == DecisionRule::Kind::kFixed) {
    r.threshold = options.rule.threshold;
  } else if (V == 0) {
    r.threshold = std::numeric_limits<double>::quiet_NaN();
    return r;
  } else {
    // Nearest rank in integers: k = ceil(P·n/100), at least 1; thr = p_(k) (ascending).
    std::vector<double> sorted(p);
    std::size_t k = (static_cast<std::size_t>(options.rule.percentile) * V + 99) / 100;
    k = std::max<std::size_t>(k, 1);
    std::nth_element(sorted.begin(), sorted.begin() + (k - 1), sorted.end());
    r.threshold = sorted[k - 1];
  }
  // Segments are computed lazily: only when some node outside R passes τ.
  std::vector<double> share;
  std::vector<std::int32_t> root;
  std::vector<std::uint8_t> segment_counted;
  for (std::size_t v = 0; v < V; ++v) {
    const auto i = static_cast<std::size_t>(problem.node_ids[v]);
    if (i >= removed.size())
      throw Error("decision: node id out of range", ExitCode::kInternal);
    const bool sel = p[v] >= r.threshold;  // exact comparison: ties go to removal
    r.selected += sel;
    r.at_threshold += p[v] == r.threshold;
    if (sel && !removed[i] && options.min_segment_share > 0.0) {
      if (share.empty()) {
        share = SegmentShares(problem, removed, root);
        segment_counted.assign(V, 0);
      }
      if (share[v] < options.min_segment_share) {
        ++r.held_back;
        if (!segment_counted[root[v]]) {
          segment_counted[root[v]] = 1;
          ++r.segments_held_back;
        }
        continue;
      }
    }
    if (sel && !removed[i]) {
      r.refined[i] = true;
      ++r.added;
    } else if (!sel && removed[i] && options.Restores()) {
      r.refined[i] = false;
      ++r.restored;
    }
  }
  return r;
}

nlohmann::json DecisionResult::ToJson() const {
  return {{"threshold", std::isfinite(threshold) ? nlohmann::json(threshold) : nlohmann::json(nullptr)},
          {"added", added},
          {"restored", restored},
          {"at_threshold", at_threshold},
          {"selected", selected},
          {"min_segment_share", min_segment_share},
          {"held_back", held_back},
          {"segments_held_back", segments_held_back}};
}

}  // namespace al
