// Tables in the paper's layout (Table 1 of the paper: rows "Scene-Object", one column group per
// metric, one column per method, best bold / second underlined) and the per-view metrics.csv.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "al/eval/eval.hpp"
#include "al/eval/view_metric.hpp"

namespace al::eval {
namespace {

std::string Fixed(double v, int digits = 2) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// Full precision for the CSV (round-trips a double).
std::string Num(double v) {
  if (!std::isfinite(v)) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string Opt(const std::optional<double>& v) { return v ? Num(*v) : ""; }

// "small_object;change_outside_object" (empty = trusted).
std::string JoinFlags(const metrics::DepthTrust& trust) {
  std::string out;
  for (const auto& f : trust.Flags()) out += (out.empty() ? "" : ";") + f;
  return out;
}

// CSV field: quoted when it holds a separator, quote or newline.
std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string LatexEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '_' || c == '&' || c == '%' || c == '#' || c == '$' || c == '{' || c == '}') out += '\\';
    out += c;
  }
  return out;
}

std::string MarkdownEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '|' || c == '*' || c == '_') out += '\\';
    out += c;
  }
  return out;
}

struct Group {
  std::string md, tex;
  bool higher_is_better = true;
  std::vector<std::optional<double>> TableRow::*values = nullptr;  // a fixed group, else
  std::size_t plugin = 0;                                          // TableRow::view_metrics[plugin]
  const std::vector<std::optional<double>>& Values(const TableRow& r) const {
    static const std::vector<std::optional<double>> none;
    if (values) return r.*values;
    return plugin < r.view_metrics.size() ? r.view_metrics[plugin] : none;
  }
};
// The residuals that were computed (the headline first: it answers "is anything of the object
// left?"), the paper's three groups, the feature metrics (no external segmenter) beside them, then
// the plug-in metrics registered with in_table (al/eval/view_metric.hpp).
std::vector<Group> ResidualGroups(const Table& t) {
  const std::vector<Group> all = {
      {"residual_gt ↓", "residual$_{\\text{gt}}\\downarrow$", false, &TableRow::residual_gt},
      {"residual_est ↓", "residual$_{\\text{est}}\\downarrow$", false, &TableRow::residual_est},
      {"residual_px ↓", "residual$_{\\text{px}}\\downarrow$", false, &TableRow::residual_px},
  };
  std::vector<Group> groups;
  for (const Group& g : all) {
    const bool lead = g.md.rfind(t.headline + " ", 0) == 0;
    const bool any = std::any_of(t.rows.begin(), t.rows.end(), [&](const TableRow& r) {
      return std::any_of((r.*g.values).begin(), (r.*g.values).end(), [](const auto& v) { return v.has_value(); });
    });
    if (any) groups.insert(lead ? groups.begin() : groups.end(), g);
  }
  return groups;
}

std::vector<Group> Groups(const Table& t) {
  std::vector<Group> groups = ResidualGroups(t);
  const std::vector<Group> paper = {
      {"IoU_drop ↑", "IoU$_{\\text{drop}}\\uparrow$", true, &TableRow::iou_drop},
      {"acc_Δdepth ↑", "acc$_{\\Delta\\text{depth}}\\uparrow$", true, &TableRow::acc_delta_depth},
      {"sim_SAM ↓", "sim$_{\\text{SAM}}\\downarrow$", false, &TableRow::sim_sam},
      {"IoU_drop_feat ↑", "IoU$_{\\text{drop}}^{\\text{feat}}\\uparrow$", true, &TableRow::iou_drop_feat},
      {"residual_feat ↓", "residual$^{\\text{feat}}\\downarrow$", false, &TableRow::residual_feat},
  };
  groups.insert(groups.end(), paper.begin(), paper.end());
  const std::vector<ViewMetric>& plugins = ViewMetrics();
  for (std::size_t k = 0; k < plugins.size(); ++k)
    if (plugins[k].in_table) groups.push_back({plugins[k].label, plugins[k].latex, plugins[k].better >= 0, nullptr, k});
  return groups;
}

// Footnote number of a cell (only the acc_Δdepth group has notes), 0 = none.
int NoteNumber(const TableRow& row, const Group& g, std::size_t method) {
  if (g.values != &TableRow::acc_delta_depth || method >= row.acc_delta_depth_note.size()) return 0;
  return row.acc_delta_depth_note[method];
}

// What the residual columns mean, for the table's note (which one leads, and what each reads).
std::string ResidualNote(const std::string& headline) {
  return "The table leads with " + headline + " (share of the object's visible signal still there: 0 = gone, "
         "1 = untouched; docs/eval.md, \"Residuals\"): residual_gt against the render without the labelled object, "
         "residual_est against the render of the first refinement (– in that refinement's own column), "
         "residual_px = share of the object mask whose colour and depth did not change.";
}

// metrics.csv's residual cells of one view and column: value and footprint size of residual_gt and
// residual_est, value of residual_px (empty = not computed or not scored).
constexpr std::size_t kResidualFields = 5;  // the last fields of a column: ResidualCells

std::string ResidualCells(const ColumnViewMetrics& m) {
  auto value = [](const std::optional<metrics::ViewResidual>& r) { return r && r->value ? Num(*r->value) : ""; };
  auto pixels = [](const std::optional<metrics::ViewResidual>& r) { return r ? std::to_string(r->pixels) : ""; };
  std::ostringstream s;
  s << ',' << value(m.residual_gt) << ',' << pixels(m.residual_gt) << ',' << value(m.residual_est) << ','
    << pixels(m.residual_est) << ',' << value(m.residual_px);
  return s.str();
}

}  // namespace

std::vector<int> RankValues(const std::vector<std::optional<double>>& values, bool higher_is_better) {
  // Ranks are decided on the printed (2-decimal) values, so two cells that read the same get the
  // same mark, as in the paper's tables.
  std::set<std::string> seen;
  std::vector<std::pair<double, std::string>> distinct;
  for (const auto& v : values)
    if (v && std::isfinite(*v) && seen.insert(Fixed(*v)).second) distinct.push_back({std::stod(Fixed(*v)), Fixed(*v)});
  std::sort(distinct.begin(), distinct.end(), [&](const auto& a, const auto& b) {
    return higher_is_better ? a.first > b.first : a.first < b.first;
  });
  std::vector<int> rank(values.size(), 0);
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!values[i] || !std::isfinite(*values[i])) continue;
    const std::string key = Fixed(*values[i]);
    if (!distinct.empty() && key == distinct[0].second) rank[i] = 1;
    else if (distinct.size() > 1 && key == distinct[1].second) rank[i] = 2;
  }
  return rank;
}

namespace {

DepthTrustNote NoteOf(const std::string& method, const metrics::DepthSummary& s) {
  DepthTrustNote n;
  n.method = method;
  n.flagged = s.flagged.size();
  n.views = s.images;
  std::map<std::string, std::vector<std::string>> by_flag;
  for (const auto& [view, flags] : s.flagged)
    for (const auto& f : flags) by_flag[f].push_back(view);
  n.views_by_flag.assign(by_flag.begin(), by_flag.end());
  if (s.acc_delta_depth_trusted.count) n.trusted_mean = s.acc_delta_depth_trusted.mean;
  return n;
}

// "fgs: acc_Δdepth cannot be trusted in 3 of 12 views (small_object: v1, v2; ...); mean over the
// 9 other views 0.52." with `esc` applied to names and `delta` for the metric's name.
std::string NoteText(const DepthTrustNote& n, std::string (*esc)(const std::string&), const std::string& delta) {
  std::ostringstream s;
  s << esc(n.method) << ": " << delta << " cannot be trusted in " << n.flagged << " of " << n.views << " views (";
  constexpr std::size_t kListed = 6;  // longer lists are cut: report.json has them all
  for (std::size_t i = 0; i < n.views_by_flag.size(); ++i) {
    const auto& [flag, views] = n.views_by_flag[i];
    s << (i ? "; " : "") << esc(flag) << ":";
    if (views.size() == n.views) {
      s << " all";
      continue;
    }
    for (std::size_t v = 0; v < std::min(views.size(), kListed); ++v) s << (v ? ", " : " ") << esc(views[v]);
    if (views.size() > kListed) s << " and " << views.size() - kListed << " more";
  }
  s << "); ";
  if (n.trusted_mean) s << "mean over the " << n.views - n.flagged << " other views " << Fixed(*n.trusted_mean) << ".";
  else s << "no view can be trusted.";
  return s.str();
}

}  // namespace

Table TableFromResult(const std::string& row_name, const std::vector<EvalColumn>& columns, const EvalResult& result) {
  Table t;
  if (!result.headline.empty()) t.headline = result.headline;
  TableRow row;
  row.name = row_name;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    t.methods.push_back(columns[c].label);
    const ColumnSummary& s = result.summaries.at(c);
    const bool any = result.evaluated > 0;
    row.iou_drop.push_back(s.semantic && s.semantic->images > 0 ? std::optional<double>(s.semantic->iou_drop)
                                                                 : std::nullopt);
    row.acc_delta_depth.push_back(any ? std::optional<double>(s.depth8.acc_delta_depth.mean) : std::nullopt);
    row.sim_sam.push_back(s.sim_sam && s.sim_sam->count > 0 ? std::optional<double>(s.sim_sam->mean) : std::nullopt);
    const bool feat = s.feature && s.feature->semantic.images > 0;
    row.iou_drop_feat.push_back(feat ? std::optional<double>(s.feature->semantic.iou_drop) : std::nullopt);
    row.residual_feat.push_back(feat && s.feature->residual.count > 0 ? std::optional<double>(s.feature->residual.mean)
                                                                       : std::nullopt);
    row.view_metrics.resize(s.view_metrics.size());
    for (std::size_t k = 0; k < s.view_metrics.size(); ++k)
      row.view_metrics[k].push_back(s.view_metrics[k].count > 0 ? std::optional<double>(s.view_metrics[k].mean)
                                                               : std::nullopt);
    auto residual = [](const std::optional<metrics::ResidualSummary>& r) {
      return r && r->stats.count > 0 ? std::optional<double>(r->stats.mean) : std::nullopt;
    };
    row.residual_gt.push_back(residual(s.residual_gt));
    row.residual_est.push_back(residual(s.residual_est));
    row.residual_px.push_back(residual(s.residual_px));
    row.acc_delta_depth_note.push_back(0);
    if (any && !s.depth8.flagged.empty()) {
      t.notes.push_back(NoteOf(columns[c].label, s.depth8));
      row.acc_delta_depth_note.back() = int(t.notes.size());
    }
  }
  t.rows.push_back(std::move(row));
  return t;
}

std::string TableMarkdown(const Table& t) {
  std::ostringstream s;
  s << "| Scene-Object |";
  const std::vector<Group> groups = Groups(t);
  for (const Group& g : groups)
    for (const auto& m : t.methods) s << ' ' << g.md << ' ' << MarkdownEscape(m) << " |";
  s << "\n|---|";
  for (std::size_t i = 0; i < groups.size() * t.methods.size(); ++i) s << "---:|";
  s << "\n";
  for (const TableRow& r : t.rows) {
    s << "| " << MarkdownEscape(r.name) << " |";
    for (const Group& g : groups) {
      const auto& v = g.Values(r);
      const std::vector<int> rank = RankValues(v, g.higher_is_better);
      for (std::size_t i = 0; i < t.methods.size(); ++i) {
        if (i >= v.size() || !v[i]) {
          s << " – |";
          continue;
        }
        const std::string x = Fixed(*v[i]);
        const int note = NoteNumber(r, g, i);
        s << ' ' << (rank[i] == 1 ? "**" + x + "**" : rank[i] == 2 ? "<u>" + x + "</u>" : x)
          << (note ? "<sup>" + std::to_string(note) + "</sup>" : "") << " |";
      }
    }
    s << "\n";
  }
  s << "\n**best** and <u>second best</u> per row and metric; – = not computed (see report.json `skipped`). "
    << ResidualNote(t.headline)
    << " IoU_drop and sim_SAM use external GroundedSAM/SAM segmentations; the _feat columns segment the "
       "scene's own rendered feature field (docs/eval.md).\n";
  for (std::size_t i = 0; i < t.notes.size(); ++i)
    s << "\n<sup>" << i + 1 << "</sup> " << NoteText(t.notes[i], MarkdownEscape, "acc_Δdepth")
      << " Flags: docs/metrics.md; per view: report.json `depth.trust`.\n";
  return s.str();
}

std::string TableLatex(const Table& t) {
  const std::size_t m = t.methods.size();
  std::ostringstream s;
  s << "% Generated by al-refine eval; needs \\usepackage{booktabs}.\n";
  s << "\\begin{tabular}{l";
  const std::vector<Group> groups = Groups(t);
  for (std::size_t g = 0; g < groups.size(); ++g) s << (g ? "|" : "") << std::string(m, 'c');
  s << "}\n  \\toprule\n  Scene-Object";
  for (const Group& g : groups) s << " & \\multicolumn{" << m << "}{c}{" << g.tex << "}";
  s << " \\\\\n  \\cmidrule(lr){2-" << 1 + groups.size() * m << "}\n ";
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (const auto& name : t.methods) s << " & " << LatexEscape(name);
  s << " \\\\\n  \\midrule\n";
  for (const TableRow& r : t.rows) {
    s << "  " << LatexEscape(r.name);
    for (const Group& g : groups) {
      const auto& v = g.Values(r);
      const std::vector<int> rank = RankValues(v, g.higher_is_better);
      for (std::size_t i = 0; i < m; ++i) {
        if (i >= v.size() || !v[i]) {
          s << " & --";
          continue;
        }
        const std::string x = Fixed(*v[i]);
        const int note = NoteNumber(r, g, i);
        s << " & " << (rank[i] == 1 ? "\\textbf{" + x + "}" : rank[i] == 2 ? "\\underline{" + x + "}" : x)
          << (note ? "$^{" + std::to_string(note) + "}$" : "");
      }
    }
    s << " \\\\\n";
  }
  s << "  \\bottomrule\n\\end{tabular}\n";
  for (std::size_t i = 0; i < t.notes.size(); ++i)
    s << "\\par\\footnotesize $^{" << i + 1 << "}$ "
      << NoteText(t.notes[i], LatexEscape, "acc$_{\\Delta\\text{depth}}$") << "\n";
  return s.str();
}

std::string MetricsCsv(const std::vector<EvalColumn>& columns, const EvalResult& result) {
  static const char* kFields[] = {"acc_delta_depth", "iou_depth", "collateral_depth", "ght_threshold",
                                  "constant_mask", "acc_delta_depth_float", "iou_depth_float",
                                  "collateral_depth_float", "collateral_psnr", "iou_before", "iou_after",
                                  "iou_drop", "sim_sam", "sim_sam_n_a", "sim_sam_n_b", "tiles_rendered",
                                  "depth_flags", "depth_float_flags", "iou_before_feat", "iou_after_feat",
                                  "iou_drop_feat", "residual_feat", "residual_gt", "footprint_gt",
                                  "residual_est", "footprint_est", "residual_px"};
  std::ostringstream s;
  const std::vector<ViewMetric>& plugins = ViewMetrics();
  s << "view,evaluated,object_pixels,width,height";
  for (const auto& c : columns) {
    for (const char* f : kFields) s << ',' << CsvField(c.name + "_" + f);
    for (const ViewMetric& p : plugins) s << ',' << CsvField(c.name + "_" + p.name);
  }
  s << "\n";
  for (const ViewRecord& v : result.views) {
    s << CsvField(v.name) << ',' << (v.evaluated ? 1 : 0) << ',' << v.object_pixels << ',' << v.width << ','
      << v.height;
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c >= v.columns.size()) {
        for (std::size_t f = 0; f < std::size(kFields) + plugins.size(); ++f) s << ',';
        continue;
      }
      if (!v.evaluated) {  // a view without the object mask: only residual_gt may be scored
        for (std::size_t f = 0; f + kResidualFields < std::size(kFields); ++f) s << ',';
        s << ResidualCells(v.columns[c]);
        for (std::size_t f = 0; f < plugins.size(); ++f) s << ',';
        continue;
      }
      const ColumnViewMetrics& m = v.columns[c];
      const bool sem = m.semantic.has_value(), sam = m.sim_sam && m.sim_sam->scored;
      s << ',' << Num(m.depth8.acc_delta_depth) << ',' << Num(m.depth8.iou) << ',' << Num(m.depth8.collateral_depth)
        << ',' << Num(m.threshold8) << ',' << (m.constant8 ? 1 : 0) << ',' << Num(m.depth_float.acc_delta_depth)
        << ',' << Num(m.depth_float.iou) << ',' << Num(m.depth_float.collateral_depth) << ','
        << Opt(m.collateral_psnr) << ',' << (sem ? Num(m.semantic->iou_before) : "") << ','
        << (sem ? Num(m.semantic->iou_after) : "") << ',' << (sem ? Num(m.semantic->iou_drop) : "") << ','
        << (sam ? Num(m.sim_sam->sim_sam) : "") << ',' << (m.sim_sam ? std::to_string(m.sim_sam->n_gt) : "")
        << ',' << (m.sim_sam ? std::to_string(m.sim_sam->n_sam) : "") << ',' << m.tiles_rendered << ','
        << CsvField(JoinFlags(m.trust8)) << ',' << CsvField(JoinFlags(m.trust_float));
      if (m.feature) {
        const metrics::FeatureRecord& f = m.feature->record;
        s << ',' << Num(f.semantic.iou_before) << ',' << Num(f.semantic.iou_after) << ',' << Num(f.semantic.iou_drop)
          << ',' << (f.before_pixels > 0 ? Num(f.residual) : "");
      } else {
        s << ",,,,";
      }
      s << ResidualCells(m);
      for (const auto& value : m.view_metrics) s << ',' << Opt(value);
    }
    s << "\n";
  }
  return s.str();
}

}  // namespace al::eval
