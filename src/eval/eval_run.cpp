// RunEval (al/eval/eval.hpp): per view, object mask → "before" render → incremental renders of
// each column → metrics → pictures; then summaries, report.json, metrics.csv and the tables.
#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/progress.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/eval/eval.hpp"
#include "al/eval/images.hpp"
#include "al/core/memory_limit.hpp"
#include "al/eval/output.hpp"
#include "al/eval/records.hpp"
#include "al/eval/report_html.hpp"
#include "al/io/ply.hpp"
#include "al/render/render_views.hpp"
#include "al/eval/report_json.hpp"
#include "al/eval/segmentations.hpp"
#include "al/metrics/removal_scores.hpp"
#include "al/io/image.hpp"
#include "al/metrics/collateral.hpp"
#include "al/metrics/mask_io.hpp"

namespace al::eval {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

bool IsDir(const std::string& p) {
  std::error_code ec;
  return !p.empty() && fs::is_directory(p, ec);
}
bool IsFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

metrics::DepthRender ToDepthRender(const RenderOutput& r) { return {r.width, r.height, r.depth, r.alpha}; }
metrics::RgbImage ToRgbImage(const RenderOutput& r) { return {r.width, r.height, r.rgb}; }

void Validate(const Scene& scene, const std::vector<Camera>& cameras, const std::vector<EvalColumn>& columns,
              const ObjectSource& object, const EvalOptions& o) {
  const std::size_t n = scene.size();
  if (o.out_dir.empty()) throw Error("eval: --out is required", ExitCode::kUsage);
  if (cameras.empty()) throw Error("eval: no views to evaluate", ExitCode::kBadInput);
  if (columns.empty()) throw Error("eval: nothing to evaluate (no removal given)", ExitCode::kUsage);
  std::map<std::string, int> names;
  for (const auto& c : columns) {
    if (c.removed.size() != n)
      throw Error("eval: removal '" + c.label + "' has " + std::to_string(c.removed.size()) +
                  " entries, the scene " + std::to_string(n));
    // Names become file-name parts (VIEW_<name>.png): they must not collide with the fixed ones.
    if (c.name.empty() || c.name == "before" || c.name == "depthdiff" || c.name == "added" ||
        c.name.find_first_of("/\\") != std::string::npos || names[c.name]++)
      throw Error("eval: column name '" + c.name + "' is empty, reserved (before, depthdiff, added), holds a path "
                  "separator or is repeated", ExitCode::kUsage);
    for (const std::string* d : {&c.seg_dir, &c.sam_dir})
      if (!d->empty() && !IsDir(*d)) throw FileError(*d, "not a directory");
  }
  for (const std::string* d : {&o.seg_before_dir, &o.sam_before_dir})
    if (!d->empty() && !IsDir(*d)) throw FileError(*d, "not a directory");
  if (!object.masks_dir.empty()) {
    if (!IsDir(object.masks_dir)) throw FileError(object.masks_dir, "object mask folder is not a directory");
  } else {
    if (object.labels.size() != n)
      throw Error("eval: labels have " + std::to_string(object.labels.size()) + " entries, the scene " +
                  std::to_string(n) + " (give --object-masks or matching --labels)");
    if (std::find(object.labels.begin(), object.labels.end(), object.object_id) == object.labels.end())
      throw Error("eval: no Gaussian has object id " + std::to_string(object.object_id) + " in the labels");
  }
  if (!(o.ght.nu >= 0) || !(o.ght.tau >= 0)) throw Error("eval: GHT nu and tau must be >= 0", ExitCode::kUsage);
  if (const std::string problem = o.trust.Check(); !problem.empty()) throw Error("eval: " + problem, ExitCode::kUsage);
}

// acc_Δdepth of one column in both modes (METRICS.md §4–§6) with the trust flags; the 8-bit pair
// and its change mask are kept for the pictures and the depth PNGs.
void ScoreDepth(const metrics::DepthRender& before, const metrics::DepthRender& after, const metrics::Mask& object,
                const EvalOptions& o, ColumnViewMetrics& m, metrics::Depth8Pair& pair, metrics::Mask& changed8) {
  pair = metrics::DepthTo8Bit(before, after, o.float_depth.alpha_hit);
  const metrics::DepthChange ch8 = metrics::DepthChange8Bit(pair.before, pair.after, o.ght, o.depth_holes);
  m.depth8 = metrics::ScoreDepthChange(&object, ch8.changed);
  m.threshold8 = ch8.threshold;
  m.constant8 = ch8.constant;
  m.trust8 = metrics::AssessDepthTrust(&object, ch8, o.trust);
  m.holes_before8 = ch8.holes_before;
  m.holes_after8 = ch8.holes_after;
  changed8 = ch8.changed;
  metrics::FloatDepthOptions fo = o.float_depth;
  fo.ght = o.ght;
  fo.holes = o.depth_holes;
  const metrics::DepthChange chf = metrics::DepthChangeFloat(before, after, fo);
  m.depth_float = metrics::ScoreDepthChange(&object, chf.changed);
  m.threshold_float = chf.threshold;
  m.trust_float = metrics::AssessDepthTrust(&object, chf, o.trust);
  m.holes_before_float = chf.holes_before;
  m.holes_after_float = chf.holes_after;
}

}  // namespace

EvalResult RunEval(const Scene& scene, const std::vector<Camera>& cameras, const std::vector<EvalColumn>& columns,
                   const ObjectSource& object, const EvalOptions& o, const json* report_in) {
  Timer total;
  Validate(scene, cameras, columns, object, o);
  const std::size_t n = scene.size(), nc = columns.size();
  EvalResult r;
  OutputSet staging(o.out_dir, EvalOutputSetOptions(o));  // --out checked before anything is computed
  if (!scene.source_path.empty())  // loaded from a file that may lack columns (in-code scenes have them all)
    for (auto& w : MissingRenderColumns(scene)) r.warnings.push_back(std::move(w));

  // Which optional metrics can run, and why not (SPEC §6: the report says what was skipped).
  std::vector<bool> run_semantic(nc), run_sam(nc);
  for (std::size_t c = 0; c < nc; ++c) {
    const std::string& col = columns[c].name;
    run_semantic[c] = !o.seg_before_dir.empty() && !columns[c].seg_dir.empty();
    run_sam[c] = !o.sam_before_dir.empty() && !columns[c].sam_dir.empty();
    if (!run_semantic[c])
      r.skipped.push_back({"iou_drop", col,
                           o.seg_before_dir.empty()
                               ? "no --seg-before: GroundedSAM masks of the before renders (write the renders with "
                                 "--export-renders, segment them, pass the mask folders back)"
                               : "no detector masks of this column's renders (--seg-after / --seg-refined)"});
    if (!run_sam[c])
      r.skipped.push_back({"sim_sam", col,
                           o.sam_before_dir.empty()
                               ? "no --sam-before: SAM segment lists of the before renders (see --export-renders)"
                               : "no SAM segment lists of this column's renders (--sam-after / --sam-refined)"});
  }

  // Feature metrics: channels and prototypes once per scene; the renders composite the channels in
  // the RGB pass (al/eval/feature_eval.hpp).
  Timer feature_timer;
  const FeatureScorer features(scene, {&object.labels, object.object_id, &columns[0].removed, &cameras}, o.feature);
  if (!features.enabled())
    for (const auto& c : columns) r.skipped.push_back({"iou_drop_feat", c.name, features.skip_reason()});
  RenderOptions render = o.render;
  render.features = features.channels();
  r.seconds_features = feature_timer.Seconds();
  const int feature_dim = render.features ? int(render.features->cols()) : 0;
  for (const Camera& cam : cameras)  // before, the incremental cache and one "after" per column, at once
    CheckMemoryEstimate("evaluating view '" + cam.name + "' at " + std::to_string(cam.width) + "x" +
                            std::to_string(cam.height) + " with " + std::to_string(nc) + " removals",
                        EstimateRenderBytes(n, cam.width, cam.height, feature_dim) * double(nc + 2));
  const fs::path out = staging.dir();
  const fs::path images = out / "images";
  if (o.write_images) EnsureDirectory(images);
  if (o.export_renders) {
    EnsureDirectory(out / "renders" / "before");
    for (const auto& c : columns) EnsureDirectory(out / "renders" / c.name);
  }
  if (o.write_depth_pngs) {
    EnsureDirectory(out / "masks");
    for (const auto& c : columns) {
      EnsureDirectory(out / "depth" / c.name / "before");
      EnsureDirectory(out / "depth" / c.name / "after");
    }
  }
  // Gaussians each refinement added to the removal method's set (column 0), for the pink overlay.
  // Restored: in the method's set, returned to the scene by the refinement (cyan in the overlay).
  std::vector<std::vector<bool>> added(nc), restored(nc);
  for (std::size_t c = 1; c < nc; ++c) {
    added[c].resize(n);
    restored[c].resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      added[c][i] = columns[c].removed[i] && !columns[0].removed[i];
      restored[c][i] = columns[0].removed[i] && !columns[c].removed[i];
    }
  }
  json view_images = json::array();  // report.html's pictures per evaluated view
  std::vector<bool> subset;
  if (object.masks_dir.empty()) {
    subset.resize(n);
    for (std::size_t i = 0; i < n; ++i) subset[i] = object.labels[i] == object.object_id;
  }
  std::unique_ptr<SamLists> sam_before;
  std::vector<std::unique_ptr<SamLists>> sam_cols(nc);
  if (!o.sam_before_dir.empty()) sam_before = std::make_unique<SamLists>(o.sam_before_dir);
  for (std::size_t c = 0; c < nc; ++c)
    if (run_sam[c]) sam_cols[c] = std::make_unique<SamLists>(columns[c].sam_dir);
  std::vector<std::size_t> sam_missing(nc, 0);
  std::size_t png_writes = 0;

  Progress progress("eval", cameras.size(), o.progress);
  for (std::size_t vi = 0; vi < cameras.size(); ++vi) {
    const Camera& cam = cameras[vi];
    ViewRecord view;
    view.name = cam.name;
    view.width = cam.width;
    view.height = cam.height;
    const std::string stem = SafeName(cam.name);

    // 1. Object mask (> 0) and its 8-bit grey form (semantic/sim_SAM binarise it themselves).
    Timer t;
    metrics::Gray8 object_gray;
    std::unique_ptr<IncrementalRenderer> renderer;
    if (!object.masks_dir.empty()) {
      const fs::path path = fs::path(object.masks_dir) / (cam.name + ".png");
      if (!IsFile(path)) {
        view.object_mask_missing = true;
        ++r.missing_object_masks;
      } else {
        object_gray = metrics::LoadGray8Png(path.string());
      }
      r.seconds_io += t.Seconds();
    } else {
      // The object's share of the "before" composite (sum of alpha*T over its Gaussians) comes out
      // of the "before" render itself: one compositing pass instead of a second one just for the
      // mask. It agrees with fixtures::SubsetWeight (the synth ground truth) up to float rounding
      // of the projection (tests/fixtures/subset_weight_render_test.cpp). Timed as render.
      RenderOptions with_share = render;
      with_share.weight_subset = &subset;
      renderer = std::make_unique<IncrementalRenderer>(scene, cam, with_share);
      r.seconds_render += t.Seconds();
      t.Reset();
      const std::vector<float>& share = renderer->before().subset_weight;
      object_gray = {cam.width, cam.height, std::vector<std::uint8_t>(share.size())};
      for (std::size_t p = 0; p < share.size(); ++p) object_gray.pixels[p] = share[p] >= 0.5f ? 255 : 0;
      r.seconds_object_masks += t.Seconds();
    }
    const metrics::Mask object_mask = metrics::Binarize(object_gray, 0);
    view.object_pixels = object_mask.Count();
    if (view.object_pixels == 0) {  // SPEC §6: views without the object are excluded and counted
      if (!view.object_mask_missing) ++r.skipped_empty_object;
      r.views.push_back(std::move(view));
      progress.Step(vi + 1);
      continue;
    }
    view.evaluated = true;
    ++r.evaluated;

    // 2. Renders: "before" in full (already done with --labels), each column incrementally from
    // its cache.
    t.Reset();
    if (!renderer) renderer = std::make_unique<IncrementalRenderer>(scene, cam, render);
    const RenderOutput& before = renderer->before();
    std::vector<RenderOutput> after(nc);
    for (std::size_t c = 0; c < nc; ++c) after[c] = renderer->After(columns[c].removed);
    r.seconds_render += t.Seconds();

    // 3. Metrics.
    t.Reset();
    const metrics::DepthRender depth_before = ToDepthRender(before);
    const metrics::RgbImage rgb_before = ToRgbImage(before);
    metrics::Gray8 seg_pre;
    bool has_seg_pre = false;
    if (!o.seg_before_dir.empty()) has_seg_pre = LoadDetectorMask(o.seg_before_dir, cam.name, o.seg_class, seg_pre);
    std::vector<metrics::Mask> sam_a;
    const bool has_sam_a = sam_before && sam_before->Load(cam.name, sam_a);
    std::vector<metrics::Depth8Pair> pairs(nc);
    std::vector<metrics::Mask> changed(nc), feature_seg(nc);
    const metrics::Mask feature_seg_before = features.enabled() ? features.Segment(before) : metrics::Mask{};
    for (std::size_t c = 0; c < nc; ++c) {
      ColumnViewMetrics m;
      m.tiles_rendered = after[c].tiles_rendered;
      ScoreDepth(depth_before, ToDepthRender(after[c]), object_mask, o, m, pairs[c], changed[c]);
      const metrics::CollateralPsnr psnr = metrics::ComputeCollateralPsnr(rgb_before, ToRgbImage(after[c]), &object_mask);
      m.collateral_psnr = psnr.psnr;
      m.identical = psnr.identical;
      if (run_semantic[c]) {
        metrics::Gray8 post;
        const bool has_post = LoadDetectorMask(columns[c].seg_dir, cam.name, o.seg_class, post);
        m.semantic = metrics::ComputeSemantic(object_gray, has_seg_pre ? &seg_pre : nullptr,
                                              has_post ? &post : nullptr, cam.name + ".png");
      }
      if (run_sam[c]) {
        std::vector<metrics::Mask> sam_b;
        const bool has_b = sam_cols[c]->Load(cam.name, sam_b);
        if (has_sam_a && has_b) m.sim_sam = metrics::ComputeSimSam(object_gray, sam_a, sam_b, o.sim_sam);
        else ++sam_missing[c];
      }
      if (features.enabled()) {
        feature_seg[c] = features.Segment(after[c]);
        m.feature = features.Score(object_mask, feature_seg_before, feature_seg[c], cam.name);
      }
      view.columns.push_back(std::move(m));
    }
    r.seconds_metrics += t.Seconds();

    // 4. Pictures and the 8-bit depth pairs (METRICS.md §6) for re-scoring elsewhere.
    t.Reset();
    // Encoded in parallel below: PNG compression dominates the I/O time.
    std::vector<std::pair<fs::path, Image8>> jobs;
    auto write = [&](const fs::path& path, Image8 img) { jobs.emplace_back(path, std::move(img)); };
    if (o.write_images) {
      json pictures = json::array();
      auto picture = [&](const std::string& key, const std::string& label, const std::string& file, Image8 img) {
        write(images / file, std::move(img));
        pictures.push_back({{"key", key}, {"label", label}, {"src", "images/" + file}});
      };
      picture("before", "before", stem + "_before.png", RenderToRgb8(before));
      for (std::size_t c = 0; c < nc; ++c)
        picture(columns[c].name, columns[c].label, stem + "_" + columns[c].name + ".png", RenderToRgb8(after[c]));
      for (std::size_t c = 0; c < nc; ++c) {
        const std::string& col = columns[c].name;
        picture(col + "_residual", columns[c].label + ": residual", stem + "_" + col + "_residual.png",
                ResidualOverlay(after[c], object_mask, changed[c]));
      }
      for (std::size_t c = 1; c < nc; ++c) {
        const std::string& col = columns[c].name;
        Image8 overlay = AddedOverlay(after[0], added[c]);
        PaintRestored(overlay, after[c], restored[c]);
        picture(col + "_added", columns[c].label + ": added / restored",
                stem + (col == "refined" ? std::string() : "_" + col) + "_added.png", std::move(overlay));
      }
      for (std::size_t c = 0; c < nc; ++c)
        picture(columns[c].name + "_depthdiff", columns[c].label + ": depth change",
                stem + (c == 0 ? std::string() : "_" + columns[c].name) + "_depthdiff.png",
                DepthDiffImage(changed[c], object_mask));
      if (features.enabled())
        for (std::size_t c = 0; c < nc; ++c)
          picture(columns[c].name + "_featseg", columns[c].label + ": feature segmentation before | after",
                  stem + (c == 0 ? std::string() : "_" + columns[c].name) + "_featseg.png",
                  FeatureSegImage(before, after[c], object_mask, feature_seg_before, feature_seg[c]));
      view_images.push_back({{"view", cam.name}, {"images", std::move(pictures)}});
    }
    if (o.export_renders) {
      write(out / "renders" / "before" / (stem + ".png"), RenderToRgb8(before));
      for (std::size_t c = 0; c < nc; ++c) write(out / "renders" / columns[c].name / (stem + ".png"), RenderToRgb8(after[c]));
    }
    if (o.write_depth_pngs) {
      write(out / "masks" / (stem + ".png"), Image8{object_gray.width, object_gray.height, 1, object_gray.pixels});
      for (std::size_t c = 0; c < nc; ++c) {
        const fs::path d = out / "depth" / columns[c].name;
        write(d / "before" / (stem + ".png"), Image8{pairs[c].before.width, pairs[c].before.height, 1, pairs[c].before.pixels});
        write(d / "after" / (stem + ".png"), Image8{pairs[c].after.width, pairs[c].after.height, 1, pairs[c].after.pixels});
      }
    }
    WritePngsParallel(jobs, o.render.num_threads);
    png_writes += jobs.size();
    r.seconds_io += t.Seconds();
    r.views.push_back(std::move(view));
    progress.Step(vi + 1);
  }
  progress.Finish();

  // Summaries over the evaluated views.
  Timer t;
  r.summaries.resize(nc);
  for (std::size_t c = 0; c < nc; ++c) {
    ColumnSummary& s = r.summaries[c];
    s.num_removed = std::size_t(std::count(columns[c].removed.begin(), columns[c].removed.end(), true));
    std::vector<metrics::DepthRecord> d8, df;
    std::vector<double> psnr, sim;
    std::vector<metrics::SemanticRecord> sem;
    std::vector<metrics::FeatureRecord> feat;
    for (const ViewRecord& v : r.views) {
      if (!v.evaluated) continue;
      const ColumnViewMetrics& m = v.columns[c];
      d8.push_back({v.name, m.depth8, m.threshold8, m.constant8, m.trust8, m.holes_before8, m.holes_after8});
      df.push_back({v.name, m.depth_float, m.threshold_float, false, m.trust_float, m.holes_before_float,
                    m.holes_after_float});
      if (m.collateral_psnr) psnr.push_back(*m.collateral_psnr);
      s.identical += m.identical;
      if (m.semantic) sem.push_back(*m.semantic);
      if (m.feature) feat.push_back(m.feature->record);
      if (m.sim_sam) {
        if (m.sim_sam->scored) sim.push_back(m.sim_sam->sim_sam);
        else ++s.sim_sam_dropped;
      }
    }
    s.depth8 = metrics::SummarizeDepth(d8);
    s.depth_float = metrics::SummarizeDepth(df);
    s.collateral_psnr = metrics::ComputeMeanStd(psnr);
    if (run_semantic[c]) s.semantic = metrics::SummarizeSemantic(sem, o.semantic);
    if (features.enabled()) s.feature = metrics::SummarizeFeature(feat, o.semantic);
    if (run_sam[c]) {
      s.sim_sam = metrics::ComputeMeanStd(sim);
      s.sim_sam_missing = sam_missing[c];
    }
  }
  if (r.evaluated == 0)
    r.warnings.push_back("no view shows the object (all object masks empty or missing): every metric is 0");
  if (r.missing_object_masks)
    r.warnings.push_back(std::to_string(r.missing_object_masks) + " view(s) without an object mask in " +
                         object.masks_dir + " were excluded");
  r.seconds_metrics += t.Seconds();

  // report.json, metrics.csv, tables.
  t.Reset();
  json report = report_in ? *report_in : NewReport("eval");
  AddEvalParams(report, columns, object, o);

  report["counts"] = {{"num_gaussians", n},
                      {"views", cameras.size()},
                      {"evaluated", r.evaluated},
                      {"skipped_empty_object", r.skipped_empty_object},
                      {"missing_object_masks", r.missing_object_masks},
                      {"png_files", png_writes}};
  json cols = json::array();
  for (std::size_t c = 0; c < nc; ++c) {
    json j = ColumnSummaryJson(columns[c], r.summaries[c], o);
    if (!object.labels.empty() && object.labels.size() == n)
      j["gt"] = ScoreRemoval(columns[c].removed, object.labels, object.object_id,
                                       std::vector<float>(scene.opacity_logits.data(),
                                                          scene.opacity_logits.data() + scene.opacity_logits.size()))
                    .ToJson();
    if (c > 0) j["added"] = std::size_t(std::count(added[c].begin(), added[c].end(), true));
    cols.push_back(std::move(j));
  }
  json skipped = json::array();
  for (const auto& s : r.skipped) skipped.push_back({{"metric", s.metric}, {"column", s.column}, {"reason", s.reason}});
  r.feature = features.ToJson();
  report["metrics"] = {{"columns", cols}, {"skipped", skipped}, {"feature_segmentation", r.feature}};
  json& warnings = report["warnings"];
  if (!warnings.is_array()) warnings = json::array();
  for (const auto& w : r.warnings) warnings.push_back(w);

  const Table table = TableFromResult(o.row_name, columns, r);
  WriteFileAtomically(out / "metrics.csv", MetricsCsv(columns, r));
  WriteFileAtomically(out / "table.md", TableMarkdown(table));
  WriteFileAtomically(out / "table.tex", TableLatex(table));
  r.outputs = {"report.json", "report.html", "metrics.csv", "table.md", "table.tex"};
  if (o.write_images) r.outputs.push_back("images/");
  if (o.write_depth_pngs) {
    r.outputs.push_back("masks/");
    r.outputs.push_back("depth/");
  }
  if (o.export_renders) r.outputs.push_back("renders/");
  report["outputs"] = r.outputs;
  r.seconds_io += t.Seconds();
  r.seconds_total = total.Seconds();
  json& timings = report["timings_s"];
  if (!timings.is_object()) timings = json::object();
  timings["object_masks"] = r.seconds_object_masks;
  timings["feature_prepare"] = r.seconds_features;
  timings["render"] = r.seconds_render;
  timings["metrics"] = r.seconds_metrics;
  timings["io"] = r.seconds_io;
  timings["eval_total"] = r.seconds_total;
  WriteFileAtomically(out / "report.html", EvalReportHtml(report, ViewRecords(columns, r), view_images));
  r.report = staging.Commit(std::move(report));
  return r;
}

}  // namespace al::eval
