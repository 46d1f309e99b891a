// The removal decision (SPEC §5, CUT_PURSUIT.md §13): refined = R ∪ { v ∈ C : p_v ≥ τ }, τ fixed
// (default 0.5) or the nearest-rank percentile of p over the nodes of C (ties go to removal).
// With restore, nodes of R with p_v < τ return to the scene.
// Segment rule [project, docs/refine.md]: a node outside R is added only if the removal method
// removed at least min_segment_share of its segment (the connected component of the graph that
// contains it, by node weight); a segment the method split is left as the method left it.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/core/option_table.hpp"
#include "al/graph/problem.hpp"

namespace al {

struct DecisionRule {
  enum class Kind { kFixed, kPercentile };
  Kind kind = Kind::kFixed;
  double threshold = 0.5;  // kFixed: τ
  int percentile = 95;     // kPercentile: P in [0, 100]
  std::string ToString() const;  // "0.5" or "percentile:95"
};

// "0.5" or "percentile:95"; throws al::Error (usage) otherwise.
DecisionRule ParseDecisionRule(const std::string& text);

// [project, docs/refine.md] Whether nodes of R with p_v < τ may return. auto = the --method
// preset's choice in the refine stages (gc: off — on synth's gc masks every restore was the object;
// every other preset: on, the feature prior doubting a removed Gaussian only where the method kept
// most of its feature group); a direct caller of ApplyDecision gets on.
enum class Restore { kAuto, kOn, kOff };

struct DecisionOptions {
  DecisionRule rule;
  Restore restore = Restore::kAuto;
  bool Restores() const { return restore != Restore::kOff; }
  // Additions need a segment removed by at least this share (0 = SPEC §5's plain rule, the
  // default). An earlier default (2/3) held back every addition where the whole candidate graph
  // is one segment the method removed only partly (docs/refine.md: what did not transfer).
  double min_segment_share = 0.0;

  static const OptionTable<DecisionOptions>& Table();  // threshold, restore, min_segment_share
  void Check() const { Table().Check(*this); }
};

struct DecisionResult {
  std::vector<bool> refined;      // N
  double threshold = 0.0;         // τ actually applied (NaN when C is empty under a percentile)
  std::size_t added = 0;          // nodes outside R now removed
  std::size_t restored = 0;       // nodes of R returned (restore only)
  std::size_t at_threshold = 0;   // nodes with p_v == τ exactly
  std::size_t selected = 0;       // nodes with p_v ≥ τ
  double min_segment_share = 0.0; // the segment rule that ran (0 = off)
  std::size_t held_back = 0;      // nodes outside R with p_v ≥ τ not added: their segment's share < min
  std::size_t segments_held_back = 0;  // segments with at least one such node
  nlohmann::json ToJson() const;
};

// removed: N (R); p: one per node of problem (node_ids map nodes to scene indices). Segments
// and shares come from problem (edges, y_remove, node_weights). Throws al::Error on size
// mismatches or a min_segment_share outside [0, 1].
DecisionResult ApplyDecision(const std::vector<bool>& removed, const RefineProblem& problem,
                             const std::vector<double>& p, const DecisionOptions& options = {});

}  // namespace al
