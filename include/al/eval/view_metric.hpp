// Per-view metrics plugged into the evaluator. One row in src/eval/view_metrics.cpp gives a metric
// its metrics.csv column (COLUMN_name), its report.json summary (metrics.columns[].view_metrics.
// name = {mean, std, count} over the evaluated views where it is defined), a row in report.html's
// summary and, with in_table, a column group in table.md/.tex. The recipe is in
// docs/architecture.md ("Add a metric").
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "al/metrics/mask.hpp"
#include "al/render/render.hpp"

namespace al::eval {

// What a metric sees of one view and one column (removal).
struct ViewMetricInput {
  const RenderOutput& before;
  const RenderOutput& after;
  const metrics::Mask& object;         // the object's pixels in the before render
  const metrics::Mask& depth_changed;  // this column's 8-bit GHT depth change (METRICS.md §4)
};

struct ViewMetric {
  std::string name;    // snake_case key: CSV column suffix, report.json key
  std::string label;   // report.html and table.md, with ↑ or ↓
  std::string latex;   // table.tex header
  int better = 0;      // +1 higher is better, -1 lower, 0 neither (no best marked)
  int digits = 3;
  bool in_table = false;  // also a column group of table.md/.tex
  std::function<std::optional<double>(const ViewMetricInput&)> compute;  // nullopt: not defined here
};

// The registered metrics, in column order.
const std::vector<ViewMetric>& ViewMetrics();

}  // namespace al::eval
