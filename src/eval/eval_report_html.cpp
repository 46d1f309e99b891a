// report.html of `eval` (al/eval/report_html.hpp).
#include "al/eval/report_html.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "al/core/html.hpp"
#include "al/eval/records.hpp"
#include "al/eval/view_metric.hpp"

namespace al::eval {
namespace {

using json = nlohmann::json;

// The rows of the summary table: a dotted key of ColumnRecords, its name, and which way is better
// (+1 higher, -1 lower, 0 neither).
struct SummaryRow {
  const char* key;
  const char* name;
  int better;
  int digits;
};
// The residuals lead (in this order the headline is always the first present: residual_gt with
// labels, else residual_est with a refinement, else residual_px; al/eval/residuals.hpp).
constexpr SummaryRow kSummaryRows[] = {
    {"residual_gt.mean", "residual_gt ↓ (share of the object still visible; ideal: the scene without it)", -1, 3},
    {"residual_est.mean", "residual_est ↓ (the same, ideal: the first refinement's render)", -1, 3},
    {"residual_px.mean", "residual_px ↓ (share of the object mask whose colour and depth did not change)", -1, 3},
    {"num_removed", "Gaussians removed", 0, 0},
    {"added", "added by the refinement", 0, 0},
    {"depth.mean_acc_delta_depth", "acc_Δdepth ↑ (8-bit, the paper's)", +1, 3},
    {"depth.trust.mean_acc_delta_depth_trusted", "acc_Δdepth ↑ (8-bit, views without a trust flag)", +1, 3},
    {"depth.trust.flagged_views", "views whose acc_Δdepth is flagged (8-bit)", 0, 0},
    {"depth_float.mean_acc_delta_depth", "acc_Δdepth ↑ (float)", +1, 3},
    {"depth.mean_iou", "IoU of depth change and object ↑", +1, 3},
    {"semantic.mean_iou_drop", "IoU_drop ↑", +1, 3},
    {"sim_sam.mean_sim_sam", "sim_SAM ↓", -1, 3},
    {"depth.collateral_depth.mean", "collateral depth ↓ (non-object pixels changed)", -1, 4},
    {"collateral_psnr.psnr.mean", "collateral PSNR ↑ (dB, outside the object)", +1, 2},
    {"gt.f1", "F1 vs ground truth ↑", +1, 3},
    {"gt.iou", "IoU vs ground truth ↑", +1, 3},
    {"gt.precision", "precision vs ground truth ↑", +1, 3},
    {"gt.recall", "recall vs ground truth ↑", +1, 3},
};

// The feature metrics (docs/eval.md, "Feature metrics"), named as in metrics.csv and the tables;
// acc_seg_feat gets one row per ξ of the report (FeatureRows).
constexpr SummaryRow kFeatureRows[] = {
    {"feature.mean_iou_drop", "IoU_drop_feat ↑", +1, 3},
    {"feature.mean_residual", "residual_feat ↓ (target's before-pixels still segmented as it)", -1, 3},
    {"feature.mean_iou_before", "IoU_before_feat (segmentation vs object mask, before)", 0, 3},
    {"feature.mean_iou_after", "IoU_after_feat ↓", -1, 3},
};

std::string Label(const json& column) { return column.value("label", column.value("name", std::string("?"))); }

// The printed best of `key` over the columns when a direction is given and the columns do not all
// print the same ("" otherwise: a row where every method ties has nothing to bold). Decided on the
// printed values, as table.md's ranks are, so that two cells that read the same are both bold.
std::string BestText(const json& columns, const std::string& key, int better, int digits) {
  double best = NAN;
  std::set<std::string> texts;
  for (const json& c : columns)
    if (c.contains(key) && c[key].is_number() && std::isfinite(c[key].get<double>()) && better != 0) {
      const double v = c[key].get<double>();
      texts.insert(HtmlNumber(v, digits));
      if (std::isnan(best) || (better > 0 ? v > best : v < best)) best = v;
    }
  return texts.size() > 1 ? HtmlNumber(best, digits) : "";
}

// One table row: the value of `key` per column, the best bold when a direction is given.
std::vector<std::string> MetricRow(const json& columns, const std::string& key, const std::string& name, int better,
                                   int digits) {
  std::vector<std::string> row = {HtmlEscape(name)};
  const std::string best = BestText(columns, key, better, digits);
  for (const json& c : columns) {
    if (!c.contains(key) || c[key].is_null()) {
      row.push_back("–");
      continue;
    }
    const json& v = c[key];
    if (!v.is_number()) {
      row.push_back(HtmlEscape(v.is_string() ? v.get<std::string>() : v.dump()));
      continue;
    }
    const std::string text = HtmlNumber(v.get<double>(), digits);
    const bool bold = !best.empty() && text == best;
    row.push_back(bold ? "<b>" + text + "</b>" : text);
  }
  return row;
}

bool AnyHas(const json& columns, const std::string& key) {
  return std::any_of(columns.begin(), columns.end(), [&](const json& c) { return c.contains(key); });
}

// The named rows of `table` present in any column; their keys go into `shown`.
template <std::size_t N>
std::vector<std::vector<std::string>> NamedRows(const json& columns, const SummaryRow (&table)[N],
                                                std::set<std::string>& shown) {
  std::vector<std::vector<std::string>> rows;
  for (const SummaryRow& r : table) {
    shown.insert(r.key);
    if (AnyHas(columns, r.key)) rows.push_back(MetricRow(columns, r.key, r.name, r.better, r.digits));
  }
  return rows;
}

// The feature table: the named rows, then acc_seg_feat per ξ (higher = better). The feature
// summary's other numbers (counts, acc before / after, ...) go with "All other metrics".
std::vector<std::vector<std::string>> FeatureRows(const json& columns, const std::set<std::string>& keys,
                                                  std::set<std::string>& shown) {
  std::vector<std::vector<std::string>> rows = NamedRows(columns, kFeatureRows, shown);
  const std::string acc_seg = "feature.acc_seg.";
  for (const std::string& key : keys)
    if (key.rfind(acc_seg, 0) == 0 && !shown.count(key)) {
      shown.insert(key);
      rows.push_back(MetricRow(columns, key, "acc_seg_feat ↑ (ξ = " + key.substr(acc_seg.size()) + ")", +1, 3));
    }
  return rows;
}

constexpr const char* kFeatureNote =
    "<p class=\"note\">Feature metrics: the target segmented in the scene's own rendered feature field "
    "(nearest prototype, no external segmenter; docs/eval.md) in the before and each after render. "
    "IoU_drop_feat and acc_seg_feat are the paper's IoU_drop and acc_seg with that segmentation in place of "
    "GroundedSAM's; residual_feat is the share of the target's before-pixels still segmented as it after "
    "(0 = nothing recognisable left).</p>\n";

std::string SummarySection(const json& columns) {
  std::vector<std::string> header = {"metric"};
  for (const json& c : columns) header.push_back(c.value("label", std::string("?")));
  std::set<std::string> shown, keys;
  std::vector<std::vector<std::string>> rows = NamedRows(columns, kSummaryRows, shown);
  for (const ViewMetric& metric : ViewMetrics()) {  // the plug-in metrics (al/eval/view_metric.hpp)
    const std::string key = "view_metrics." + metric.name + ".mean";
    shown.insert(key);
    if (AnyHas(columns, key)) rows.push_back(MetricRow(columns, key, metric.label, metric.better, metric.digits));
  }
  for (const json& c : columns)
    for (const auto& [key, value] : c.items())
      if (value.is_number()) keys.insert(key);
  const std::vector<std::vector<std::string>> feature_rows = FeatureRows(columns, keys, shown);
  std::vector<std::vector<std::string>> other_rows;
  for (const std::string& key : keys)
    if (!shown.count(key)) other_rows.push_back(MetricRow(columns, key, key, 0, 4));
  std::string s = "<h2>Summary</h2>\n" + HtmlTable(header, rows, "summary") +
                  "<p class=\"note\">Bold: the best value of a row. The residuals answer \"is anything of the "
                  "object left?\" (0 = gone, 1 = untouched; docs/eval.md, \"Residuals\", says how far each can be "
                  "trusted; residual_est is – for the first refinement: its render is the ideal); the paper's "
                  "figures follow. acc_Δdepth: share of the object's pixels whose depth changed "
                  "(1 = the object is gone), thresholded over the whole image.</p>\n";
  if (!feature_rows.empty())
    s += "<h2>Feature metrics</h2>\n" + HtmlTable(header, feature_rows, "summary") + kFeatureNote;
  if (!other_rows.empty())
    s += "<details><summary>All other metrics of report.json</summary>\n" + HtmlTable(header, other_rows) +
         "</details>\n";
  return s;
}

std::string NotesSection(const json& report) {
  std::string s;
  const json warnings = report.value("warnings", json::array());
  const json skipped = report.contains("metrics") ? report["metrics"].value("skipped", json::array()) : json::array();
  if (!warnings.empty()) {
    s += "<h2>Warnings</h2>\n<ul class=\"warn\">";
    for (const json& w : warnings) s += "<li>" + HtmlEscape(w.is_string() ? w.get<std::string>() : w.dump()) + "</li>";
    s += "</ul>\n";
  }
  if (!skipped.empty()) {
    std::set<std::string> lines;
    for (const json& k : skipped)
      lines.insert(k.value("metric", std::string()) + ": " + k.value("reason", std::string()));
    s += "<details><summary>Metrics not computed (" + std::to_string(skipped.size()) + ")</summary><ul class=\"note\">";
    for (const auto& line : lines) s += "<li>" + HtmlEscape(line) + "</li>";
    s += "</ul></details>\n";
  }
  return s;
}

void AddFlag(std::map<std::string, std::vector<std::string>>& out, const std::string& view, const std::string& text) {
  auto& list = out[view];
  if (std::find(list.begin(), list.end(), text) == list.end()) list.push_back(text);
}

// Every "flagged" array below `value` (see FlaggedViews); `label` names the column and the summary
// it is in ("fgs, depth").
void CollectFlagged(const json& value, const std::string& label, std::map<std::string, std::vector<std::string>>& out) {
  if (!value.is_object()) return;
  for (const auto& [key, item] : value.items()) {
    if (key != "flagged" || !item.is_array()) {
      CollectFlagged(item, label, out);
      continue;
    }
    for (const json& entry : item) {
      if (entry.is_string()) {
        AddFlag(out, entry.get<std::string>(), label + ": flagged");
        continue;
      }
      if (!entry.is_object()) continue;
      const std::string view = entry.value("view", entry.value("image", std::string()));
      const json flags = entry.value("flags", json::array());
      if (flags.is_array() && !flags.empty())
        for (const json& f : flags) AddFlag(out, view, label + ": " + (f.is_string() ? f.get<std::string>() : f.dump()));
      else AddFlag(out, view, label + ": " + (flags.is_string() ? flags.get<std::string>() : "flagged"));
    }
  }
}

// The headline residual of a view and column (metrics.csv's COLUMN_residual_gt, ...); on
// residual_est's own ideal column, its residual_px. NaN when the view has none.
double Residual(const json& record, const std::string& column, const std::string& headline) {
  for (const std::string& key : {column + "_" + headline, column + "_residual_px"})
    if (record.contains(key) && record[key].is_number()) return record[key].get<double>();
  return NAN;
}

// One badge per flag name, with the columns / summaries that raised it ("fgs, depth; fgs+bk, depth").
std::map<std::string, std::string> FlagBadges(const std::vector<std::string>& flags) {
  std::map<std::string, std::string> badges;
  for (const std::string& text : flags) {
    const auto colon = text.rfind(": ");
    const std::string flag = colon == std::string::npos ? text : text.substr(colon + 2);
    const std::string source = colon == std::string::npos ? "" : text.substr(0, colon);
    std::string& sources = badges[flag];
    sources += (sources.empty() ? "" : "; ") + source;
  }
  return badges;
}

std::string ImageOptions(const json& images, const std::string& selected) {
  std::string s;
  for (const json& im : images) {
    const std::string src = UrlPath(im.value("src", std::string()));
    s += "<option value=\"" + HtmlEscape(src) + "\"" + (im.value("key", std::string()) == selected ? " selected" : "") +
         ">" + HtmlEscape(im.value("label", std::string())) + "</option>";
  }
  return s;
}

std::string SrcOf(const json& images, const std::string& key) {
  for (const json& im : images)
    if (im.value("key", std::string()) == key) return UrlPath(im.value("src", std::string()));
  return images.empty() ? std::string() : UrlPath(images[0].value("src", std::string()));
}

// " — residual_feat fgs 0.02 · fgs+bk 0.01" from a view's metrics.csv record; empty without feature metrics.
std::string ResidualFeatText(const json& record, const json& columns) {
  std::string s;
  for (const json& c : columns) {
    const std::string key = c.value("name", std::string()) + "_residual_feat";
    if (!record.contains(key) || !record[key].is_number()) continue;
    s += (s.empty() ? " — residual_feat " : " · ") + HtmlEscape(Label(c)) + " " +
         HtmlNumber(record[key].get<double>(), 2);
  }
  return s;
}

// One view: the pictures side by side, then a wipe between any two of them.
std::string ViewCard(const json& entry, const json* record, const json& columns, const std::vector<std::string>* flags,
                     const std::string& headline) {
  const std::string view = entry.value("view", std::string());
  const json& images = entry["images"];
  std::string residuals;
  for (const json& c : columns) {
    const double r = record ? Residual(*record, c.value("name", std::string()), headline) : NAN;
    residuals += (residuals.empty() ? headline + " " : " · ") + HtmlEscape(Label(c)) + " " + HtmlNumber(r, 2);
  }
  if (record) residuals += ResidualFeatText(*record, columns);
  std::string s = "<section class=\"view" + std::string(flags ? " flagged" : "") + "\" id=\"view-" +
                  HtmlEscape(UrlPath(view)) + "\">\n<h3>" + HtmlEscape(view) + " <span class=\"note\">" + residuals +
                  "</span>";
  if (flags)
    for (const auto& [flag, sources] : FlagBadges(*flags))
      s += "<span class=\"flag\" title=\"acc_Δdepth of this view cannot be trusted: " + HtmlEscape(sources) +
           "\">⚑ " + HtmlEscape(flag) + "</span>";
  s += "</h3>\n<div class=\"strip\">";
  for (const json& im : images)
    s += "<figure><img alt=\"" + HtmlEscape(im.value("label", std::string())) + "\" src=\"" +
         HtmlEscape(UrlPath(im.value("src", std::string()))) + "\"><figcaption>" +
         HtmlEscape(im.value("label", std::string())) + "</figcaption></figure>";
  const std::string last = columns.empty() ? "before" : columns.back().value("name", std::string());
  s += "</div>\n<div class=\"controls\">wipe from <select class=\"wipe-a\">" + ImageOptions(images, "before") +
       "</select> to <select class=\"wipe-b\">" + ImageOptions(images, last) +
       "</select> <input class=\"wipe\" type=\"range\" min=\"0\" max=\"100\" value=\"50\" aria-label=\"wipe\"></div>\n"
       "<div class=\"compare\"><img class=\"bottom\" alt=\"wipe base\" src=\"" + HtmlEscape(SrcOf(images, last)) +
       "\"><img class=\"top\" alt=\"wipe top\" src=\"" + HtmlEscape(SrcOf(images, "before")) + "\"></div>\n</section>\n";
  return s;
}

// The wipe: the left part of the compare box shows select A, the rest select B.
constexpr const char* kWipeScript = R"js(
document.addEventListener('input', function (event) {
  var card = event.target.closest('section.view');
  if (!card) return;
  var a = card.querySelector('select.wipe-a'), b = card.querySelector('select.wipe-b');
  var wipe = card.querySelector('input.wipe');
  var top = card.querySelector('.compare img.top'), bottom = card.querySelector('.compare img.bottom');
  top.src = a.value;
  bottom.src = b.value;
  top.style.clipPath = 'inset(0 ' + (100 - Number(wipe.value)) + '% 0 0)';
});
)js";

std::string ViewsSection(const json& columns, const json& view_records, const json& view_images,
                         const std::map<std::string, std::vector<std::string>>& flagged, const std::string& headline) {
  std::map<std::string, const json*> by_view;
  for (const json& r : view_records) by_view[r.value("view", std::string())] = &r;
  const std::string first = columns.empty() ? "" : columns.front().value("name", std::string());
  std::vector<std::pair<double, const json*>> order;
  for (const json& entry : view_images) {
    const auto it = by_view.find(entry.value("view", std::string()));
    const double r = it == by_view.end() ? NAN : Residual(*it->second, first, headline);
    order.push_back({std::isnan(r) ? -1.0 : r, &entry});
  }
  std::stable_sort(order.begin(), order.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  std::string s = "<h2>Views, by " + HtmlEscape(headline) + " of " +
                  HtmlEscape(columns.empty() ? "" : Label(columns.front())) +
                  " (most left of the object first)</h2>\n<p class=\"note\">Residual overlay (" + HtmlEscape(headline) +
                  "): red in proportion to how much of the object each pixel still shows, the object's footprint "
                  "outlined green. Added overlay: pixels whose front Gaussian the refinement "
                  "added (pink) or restored (cyan). Flagged views (outlined, ⚑): acc_Δdepth cannot be trusted "
                  "there. Drag the slider to wipe between any two pictures.</p>\n";
  for (const auto& [residual, entry] : order) {
    const std::string view = entry->value("view", std::string());
    const auto rec = by_view.find(view);
    const auto flags = flagged.find(view);
    s += ViewCard(*entry, rec == by_view.end() ? nullptr : rec->second, columns,
                  flags == flagged.end() ? nullptr : &flags->second, headline);
  }
  return s;
}

}  // namespace

std::map<std::string, std::vector<std::string>> FlaggedViews(const json& report, const json& view_records) {
  std::map<std::string, std::vector<std::string>> out;
  if (report.contains("metrics") && report["metrics"].contains("columns"))
    for (const json& column : report["metrics"]["columns"])
      for (const auto& [key, summary] : column.items()) CollectFlagged(summary, Label(column) + ", " + key, out);
  if (!out.empty()) return out;  // metrics.csv repeats what report.json says; it counts only alone
  for (const json& record : view_records)
    for (const auto& [key, value] : record.items())
      if (key.find("flag") != std::string::npos && value.is_string() && !value.get<std::string>().empty())
        AddFlag(out, record.value("view", std::string()), key + ": " + value.get<std::string>());
  return out;
}

}  // namespace al::eval

namespace al::eval {

std::string EvalReportHtml(const json& report, const json& view_records, const json& view_images) {
  const json columns = ColumnRecords(report);
  const std::string row = report.value("params", json::object()).value("row_name", std::string("evaluation"));
  const json counts = report.value("counts", json::object());
  const auto flagged = FlaggedViews(report, view_records);
  std::string body = "<h1>al-refine eval: " + HtmlEscape(row) + "</h1>\n<p class=\"note\">" +
                     std::to_string(counts.value("evaluated", 0)) + " of " + std::to_string(counts.value("views", 0)) +
                     " views show the object and were evaluated; " + std::to_string(flagged.size()) +
                     " flagged. Numbers: report.json, metrics.csv; tables: table.md, table.tex.</p>\n";
  body += SummarySection(columns);
  body += NotesSection(report);
  const json metrics = report.value("metrics", json::object());
  const std::string headline =
      metrics.value("residuals", json::object()).value("headline", std::string("residual_px"));
  body += ViewsSection(columns, view_records, view_images, flagged, headline);
  return HtmlPage("al-refine eval: " + row, body, kWipeScript);
}

}  // namespace al::eval
