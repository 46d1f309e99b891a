// Threshold rules over solver output (see decision.hpp).
#include "al/decision.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "al/core/error.hpp"

namespace al {

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
      throw Error("--threshold: '" + text + "': expected percentile:P with an integer P in [0, 100]",
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
    throw Error("--threshold: '" + text + "': expected a number (e.g. 0.5) or percentile:95",
                ExitCode::kUsage);
  rule.threshold = t;
  return rule;
}

DecisionResult ApplyDecision(const std::vector<bool>& removed, const RefineProblem& problem,
                             const std::vector<double>& p, const DecisionOptions& options) {
  const std::size_t V = problem.num_nodes();
  if (p.size() != V || problem.node_ids.size() != V)
    throw Error("decision: solver output has " + std::to_string(p.size()) + " values for " +
                std::to_string(V) + " nodes", ExitCode::kInternal);
  DecisionResult r;
  r.refined = removed;
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
  for (std::size_t v = 0; v < V; ++v) {
    const auto i = static_cast<std::size_t>(problem.node_ids[v]);
    if (i >= removed.size())
      throw Error("decision: node id out of range", ExitCode::kInternal);
    const bool sel = p[v] >= r.threshold;  // exact comparison: ties go to removal
    r.selected += sel;
    r.at_threshold += p[v] == r.threshold;
    if (sel && !removed[i]) {
      r.refined[i] = true;
      ++r.added;
    } else if (!sel && removed[i] && options.restore) {
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
          {"selected", selected}};
}

}  // namespace al
