// report.html of sweep / merge (al/refine/sweep.hpp): charts, Pareto table, best settings per scene.
#include <algorithm>
#include <cmath>
#include <map>

#include "al/core/html.hpp"
#include "al/refine/sweep.hpp"

namespace al {
namespace {

using json = nlohmann::json;

std::string Param(const json& params, const char* key) {
  if (!params.contains(key)) return "–";
  const json& v = params[key];
  return HtmlEscape(v.is_string() ? v.get<std::string>() : v.dump());
}

std::string ParetoSection(const std::vector<ParetoPoint>& points) {
  if (points.empty()) return "<p class=\"note\">No record has ground-truth F1 (give --labels): no Pareto table.</p>\n";
  std::vector<const ParetoPoint*> order;
  for (const auto& p : points) order.push_back(&p);
  std::stable_sort(order.begin(), order.end(), [](const auto* a, const auto* b) {
    return a->on_front != b->on_front ? a->on_front : a->error != b->error ? a->error < b->error : a->seconds < b->seconds;
  });
  std::vector<std::vector<std::string>> rows;
  for (const auto* p : order)
    rows.push_back({p->on_front ? "<b>front</b>" : "", HtmlEscape(p->solver), Param(p->params, "k"),
                    Param(p->params, "delta"), Param(p->params, "hops"), Param(p->params, "radius_scale"),
                    Param(p->params, "lambda"), Param(p->params, "threshold"), Param(p->params, "segment_share"),
                    HtmlNumber(1.0 - p->error, 4), HtmlNumber(p->seconds, 3), std::to_string(p->scenes)});
  return "<h2>Pareto table</h2>\n<p class=\"note\">Each setting's mean over the scenes with ground truth: "
         "F1 after refinement and run time (graph build + solve). The front (no setting both faster and "
         "more accurate) first, then by error.</p>\n" +
         HtmlTable({"", "solver", "k", "δ", "hops", "radius", "λ", "threshold", "segment share", "F1", "seconds",
                    "scenes"},
                   rows, "summary");
}

// Per scene: the record with the best F1 after refinement, and its gain over the input.
std::string BestPerScene(const std::vector<json>& records) {
  std::map<std::string, const json*> best;
  for (const json& r : records) {
    if (!r.contains("gt") || !r["gt"]["after"].contains("f1")) continue;
    const std::string scene = r.value("scene", std::string());
    const double f1 = r["gt"]["after"]["f1"].get<double>();
    if (!best.count(scene) || f1 > (*best[scene])["gt"]["after"]["f1"].get<double>()) best[scene] = &r;
  }
  if (best.empty()) return "";
  std::vector<std::vector<std::string>> rows;
  for (const auto& [scene, r] : best) {
    const json& p = (*r)["params"];
    rows.push_back({HtmlEscape(scene), Param(p, "solver"), Param(p, "k"), Param(p, "delta"), Param(p, "lambda"),
                    Param(p, "threshold"), HtmlNumber((*r)["gt"]["before"].value("f1", NAN), 4),
                    HtmlNumber((*r)["gt"]["after"]["f1"].get<double>(), 4)});
  }
  return "<h2>Best setting per scene</h2>\n" +
         HtmlTable({"scene", "solver", "k", "δ", "λ", "threshold", "F1 input", "F1 refined"}, rows, "summary");
}

}  // namespace

std::string SweepReportHtml(const std::vector<json>& records, const json& summaries) {
  std::map<std::string, int> scenes;
  for (const json& r : records) ++scenes[r.value("scene", std::string())];
  std::string body = "<h1>al-refine sweep</h1>\n<p class=\"note\">" + std::to_string(records.size()) +
                     " records over " + std::to_string(scenes.size()) +
                     " scene(s). Numbers: results.jsonl, results.csv; charts drawn by gnuplot from the .gp and "
                     ".dat files beside them.</p>\n";
  const json charts = summaries.value("charts", json::array());
  if (!charts.empty()) {
    body += "<h2>Charts</h2>\n";
    for (const json& c : charts) {
      const std::string name = c.get<std::string>();
      body += "<figure><img alt=\"" + HtmlEscape(name) + "\" src=\"" + HtmlEscape(UrlPath(name)) +
              "\" style=\"max-width:100%\"><figcaption>" + HtmlEscape(name) + "</figcaption></figure>\n";
    }
  }
  for (const json& s : summaries.value("skipped_charts", json::array()))
    body += "<p class=\"note warn\">Chart " + HtmlEscape(s.value("name", std::string())) + " not drawn: " +
            HtmlEscape(s.value("reason", std::string())) + "</p>\n";
  body += ParetoSection(ParetoPoints(records));
  body += BestPerScene(records);
  return HtmlPage("al-refine sweep", body);
}

}  // namespace al
