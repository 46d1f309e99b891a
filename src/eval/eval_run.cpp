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
#include "al/eval/residuals.hpp"
#include "al/eval/segmentations.hpp"
#include "al/eval/view_metric.hpp"
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
  o.Check();
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

// What the run decides once and every view reads: which optional metrics run, the Gaussians each
// refinement added or restored, the object's Gaussians, the segment lists, the output folders.
struct EvalContext {
  EvalContext(const Scene& s, const std::vector<EvalColumn>& c, const ObjectSource& ob, const EvalOptions& op,
              const std::vector<Camera>& cameras)
      : scene(s), columns(c), object(ob), o(op),
        features(s, {&ob.labels, ob.object_id, &c[0].removed, &cameras}, op.feature) {}
  const Scene& scene;
  const std::vector<EvalColumn>& columns;
  const ObjectSource& object;
  const EvalOptions& o;
  FeatureScorer features;
  RenderOptions render;
  fs::path out, images;
  std::string headline;  // the residual that leads (al/eval/residuals.hpp)
  metrics::ResidualOptions residual;  // o.residual with the depth metrics' alpha_hit
  std::vector<bool> run_semantic, run_sam, subset;
  std::vector<bool> target;  // the labels' target (residual_gt's ideal removes it); empty without labels
  std::vector<std::vector<bool>> added, restored;
  std::unique_ptr<SamLists> sam_before;
  std::vector<std::unique_ptr<SamLists>> sam_cols;
  std::vector<std::size_t> sam_missing;
  std::size_t png_writes = 0;
  json view_images = json::array();  // report.html's pictures per evaluated view
};

// Which optional metrics can run, and why not (SPEC §6: the report says what was skipped).
void PlanOptionalMetrics(EvalContext& ctx, EvalResult& r) {
  const EvalOptions& o = ctx.o;
  const std::size_t nc = ctx.columns.size();
  ctx.run_semantic.assign(nc, false);
  ctx.run_sam.assign(nc, false);
  for (std::size_t c = 0; c < nc; ++c) {
    const std::string& col = ctx.columns[c].name;
    ctx.run_semantic[c] = !o.seg_before_dir.empty() && !ctx.columns[c].seg_dir.empty();
    ctx.run_sam[c] = !o.sam_before_dir.empty() && !ctx.columns[c].sam_dir.empty();
    if (!ctx.run_semantic[c])
      r.skipped.push_back({"iou_drop", col,
                           o.seg_before_dir.empty()
                               ? "no --seg-before: GroundedSAM masks of the before renders (write the renders with "
                                 "--export-renders, segment them, pass the mask folders back)"
                               : "no detector masks of this column's renders (--seg-after / --seg-refined)"});
    if (!ctx.run_sam[c])
      r.skipped.push_back({"sim_sam", col,
                           o.sam_before_dir.empty()
                               ? "no --sam-before: SAM segment lists of the before renders (see --export-renders)"
                               : "no SAM segment lists of this column's renders (--sam-after / --sam-refined)"});
  }
  if (!ctx.features.enabled())
    for (const auto& c : ctx.columns) r.skipped.push_back({"iou_drop_feat", c.name, ctx.features.skip_reason()});
  if (ctx.target.empty())
    for (const auto& c : ctx.columns)
      r.skipped.push_back({"residual_gt", c.name, "no --labels: the ground-truth ideal (the scene without the object) "
                                                  "needs them"});
  if (nc < 2)
    r.skipped.push_back({"residual_est", ctx.columns[0].name,
                         "no --refined: residual_est takes the first refinement's render as the ideal"});
}

// Before, the incremental cache, one "after" per column and the ideal are held at once for each view.
void CheckEvalMemory(const EvalContext& ctx, const std::vector<Camera>& cameras) {
  const std::size_t n = ctx.scene.size(), nc = ctx.columns.size();
  const int feature_dim = ctx.render.features ? int(ctx.render.features->cols()) : 0;
  for (const Camera& cam : cameras)
    CheckMemoryEstimate("evaluating view '" + cam.name + "' at " + std::to_string(cam.width) + "x" +
                            std::to_string(cam.height) + " with " + std::to_string(nc) + " removals",
                        EstimateRenderBytes(n, cam.width, cam.height, feature_dim) * double(nc + 3));
}

void MakeOutputFolders(const EvalContext& ctx) {
  if (ctx.o.write_images) EnsureDirectory(ctx.images);
  if (ctx.o.export_renders) {
    EnsureDirectory(ctx.out / "renders" / "before");
    for (const auto& c : ctx.columns) EnsureDirectory(ctx.out / "renders" / c.name);
  }
  if (!ctx.o.write_depth_pngs) return;
  EnsureDirectory(ctx.out / "masks");
  for (const auto& c : ctx.columns) {
    EnsureDirectory(ctx.out / "depth" / c.name / "before");
    EnsureDirectory(ctx.out / "depth" / c.name / "after");
  }
}

// Added: in a refinement's set but not the method's (column 0), pink in the overlay. Restored: in
// the method's set, returned to the scene by the refinement (cyan). Subset: the object's Gaussians.
void MarkGaussians(EvalContext& ctx) {
  const std::size_t n = ctx.scene.size(), nc = ctx.columns.size();
  ctx.added.assign(nc, {});
  ctx.restored.assign(nc, {});
  for (std::size_t c = 1; c < nc; ++c) {
    ctx.added[c].resize(n);
    ctx.restored[c].resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      ctx.added[c][i] = ctx.columns[c].removed[i] && !ctx.columns[0].removed[i];
      ctx.restored[c][i] = ctx.columns[0].removed[i] && !ctx.columns[c].removed[i];
    }
  }
  if (!ctx.object.labels.empty() && ctx.object.labels.size() == n) {
    ctx.target.resize(n);
    for (std::size_t i = 0; i < n; ++i) ctx.target[i] = ctx.object.labels[i] == ctx.object.object_id;
  }
  if (!ctx.object.masks_dir.empty()) return;
  ctx.subset.resize(n);
  for (std::size_t i = 0; i < n; ++i) ctx.subset[i] = ctx.object.labels[i] == ctx.object.object_id;
}

void OpenSamLists(EvalContext& ctx) {
  const std::size_t nc = ctx.columns.size();
  if (!ctx.o.sam_before_dir.empty()) ctx.sam_before = std::make_unique<SamLists>(ctx.o.sam_before_dir);
  ctx.sam_cols.resize(nc);
  for (std::size_t c = 0; c < nc; ++c)
    if (ctx.run_sam[c]) ctx.sam_cols[c] = std::make_unique<SamLists>(ctx.columns[c].sam_dir);
  ctx.sam_missing.assign(nc, 0);
}

// Step 1: the object mask (> 0) of a view, in 8-bit grey (semantic / sim_SAM binarise it
// themselves). From --object-masks, or from the "before" render with --labels (then the renderer
// is created here and kept). False when the mask file is missing.
bool ObjectMaskOf(EvalContext& ctx, const Camera& cam, EvalResult& r, metrics::Gray8& gray,
                  std::unique_ptr<IncrementalRenderer>& renderer) {
  Timer t;
  if (!ctx.object.masks_dir.empty()) {
    const fs::path path = fs::path(ctx.object.masks_dir) / (cam.name + ".png");
    const bool found = IsFile(path);
    if (found) gray = metrics::LoadGray8Png(path.string());
    r.seconds_io += t.Seconds();
    return found;
  }
  // The object's share of the "before" composite (sum of alpha*T over its Gaussians) comes out of
  // the "before" render itself: one compositing pass instead of a second one just for the mask. It
  // agrees with fixtures::SubsetWeight (the synth ground truth) up to float rounding of the
  // projection (tests/fixtures/subset_weight_render_test.cpp). Timed as render.
  RenderOptions with_share = ctx.render;
  with_share.weight_subset = &ctx.subset;
  renderer = std::make_unique<IncrementalRenderer>(ctx.scene, cam, with_share);
  r.seconds_render += t.Seconds();
  t.Reset();
  const std::vector<float>& share = renderer->before().subset_weight;
  gray = {cam.width, cam.height, std::vector<std::uint8_t>(share.size())};
  for (std::size_t p = 0; p < share.size(); ++p) gray.pixels[p] = share[p] >= 0.5f ? 255 : 0;
  r.seconds_object_masks += t.Seconds();
  return true;
}

// The renders and masks of one evaluated view that the metrics and the pictures share.
struct ViewRenders {
  const RenderOutput* before = nullptr;
  std::vector<RenderOutput> after;
  std::optional<RenderOutput> ideal;  // without the labels' target (residual_gt)
  std::vector<std::vector<float>> residual_share;  // per column: the headline residual per pixel
  metrics::Gray8 object_gray;
  metrics::Mask object_mask, feature_seg_before;
  std::vector<metrics::Depth8Pair> pairs;
  std::vector<metrics::Mask> changed, feature_seg;
};

// The detector (GroundedSAM) IoU and sim_SAM of column c, when their inputs exist.
void ScoreSegmentations(EvalContext& ctx, const Camera& cam, std::size_t c, const metrics::Gray8* seg_pre,
                        const std::vector<metrics::Mask>* sam_a, const metrics::Gray8& object_gray,
                        ColumnViewMetrics& m) {
  if (ctx.run_semantic[c]) {
    metrics::Gray8 post;
    const bool has_post = LoadDetectorMask(ctx.columns[c].seg_dir, cam.name, ctx.o.seg_class, post);
    m.semantic = metrics::ComputeSemantic(object_gray, seg_pre, has_post ? &post : nullptr, cam.name + ".png");
  }
  if (!ctx.run_sam[c]) return;
  std::vector<metrics::Mask> sam_b;
  const bool has_b = ctx.sam_cols[c]->Load(cam.name, sam_b);
  if (sam_a && has_b) m.sim_sam = metrics::ComputeSimSam(object_gray, *sam_a, sam_b, ctx.o.sim_sam);
  else ++ctx.sam_missing[c];
}

// Step 3: every metric of every column on one view.
void ScoreView(EvalContext& ctx, const Camera& cam, ViewRenders& v, ViewRecord& view) {
  const std::size_t nc = ctx.columns.size();
  const metrics::DepthRender depth_before = ToDepthRender(*v.before);
  const metrics::RgbImage rgb_before = ToRgbImage(*v.before);
  metrics::Gray8 seg_pre;
  const bool has_seg_pre = !ctx.o.seg_before_dir.empty() &&
                           LoadDetectorMask(ctx.o.seg_before_dir, cam.name, ctx.o.seg_class, seg_pre);
  std::vector<metrics::Mask> sam_a;
  const bool has_sam_a = ctx.sam_before && ctx.sam_before->Load(cam.name, sam_a);
  v.pairs.resize(nc);
  v.changed.resize(nc);
  v.feature_seg.resize(nc);
  v.residual_share.resize(nc);
  if (ctx.features.enabled()) v.feature_seg_before = ctx.features.Segment(*v.before);
  for (std::size_t c = 0; c < nc; ++c) {
    ColumnViewMetrics m;
    m.tiles_rendered = v.after[c].tiles_rendered;
    ScoreDepth(depth_before, ToDepthRender(v.after[c]), v.object_mask, ctx.o, m, v.pairs[c], v.changed[c]);
    const metrics::CollateralPsnr psnr = metrics::ComputeCollateralPsnr(rgb_before, ToRgbImage(v.after[c]), &v.object_mask);
    m.collateral_psnr = psnr.psnr;
    m.identical = psnr.identical;
    ScoreSegmentations(ctx, cam, c, has_seg_pre ? &seg_pre : nullptr, has_sam_a ? &sam_a : nullptr, v.object_gray, m);
    for (const ViewMetric& metric : ViewMetrics())
      m.view_metrics.push_back(metric.compute({*v.before, v.after[c], v.object_mask, v.changed[c]}));
    const RenderOutput* ideal_est = nc > 1 && c != 1 ? &v.after[1] : nullptr;
    ScoreResiduals({*v.before, v.after[c], v.ideal ? &*v.ideal : nullptr, ideal_est, v.object_mask}, ctx.residual, ctx.headline, m,
                   v.residual_share[c]);
    if (ctx.features.enabled()) {
      v.feature_seg[c] = ctx.features.Segment(v.after[c]);
      m.feature = ctx.features.Score(v.object_mask, v.feature_seg_before, v.feature_seg[c], cam.name);
    }
    view.columns.push_back(std::move(m));
  }
}

using PngJobs = std::vector<std::pair<fs::path, Image8>>;

// Which residual a column's overlay shows: the headline, except on residual_est's own ideal.
std::string ResidualShown(const EvalContext& ctx, std::size_t c) {
  return ctx.headline == "residual_est" && c == 1 ? "residual_px" : ctx.headline;
}

// Step 4a: report.html's pictures of one view (before, after, residual, added, depth change, feature
// segmentation), queued as PNG jobs.
void QueuePictures(EvalContext& ctx, const Camera& cam, const ViewRenders& v, PngJobs& jobs) {
  const std::vector<EvalColumn>& columns = ctx.columns;
  const std::size_t nc = columns.size();
  const std::string stem = SafeName(cam.name);
  json pictures = json::array();
  auto picture = [&](const std::string& key, const std::string& label, const std::string& file, Image8 img) {
    jobs.emplace_back(ctx.images / file, std::move(img));
    pictures.push_back({{"key", key}, {"label", label}, {"src", "images/" + file}});
  };
  auto suffix = [&](std::size_t c) { return c == 0 ? std::string() : "_" + columns[c].name; };
  picture("before", "before", stem + "_before.png", RenderToRgb8(*v.before));
  if (v.ideal) picture("ideal", "ideal (without the object)", stem + "_ideal.png", RenderToRgb8(*v.ideal));
  for (std::size_t c = 0; c < nc; ++c)
    picture(columns[c].name, columns[c].label, stem + "_" + columns[c].name + ".png", RenderToRgb8(v.after[c]));
  for (std::size_t c = 0; c < nc; ++c)
    picture(columns[c].name + "_residual", columns[c].label + ": " + ResidualShown(ctx, c),
            stem + "_" + columns[c].name + "_residual.png", ResidualOverlay(v.after[c], v.residual_share[c]));
  for (std::size_t c = 1; c < nc; ++c) {
    Image8 overlay = AddedOverlay(v.after[0], ctx.added[c]);
    PaintRestored(overlay, v.after[c], ctx.restored[c]);
    picture(columns[c].name + "_added", columns[c].label + ": added / restored",
            stem + (columns[c].name == "refined" ? std::string() : suffix(c)) + "_added.png", std::move(overlay));
  }
  for (std::size_t c = 0; c < nc; ++c)
    picture(columns[c].name + "_depthdiff", columns[c].label + ": depth change", stem + suffix(c) + "_depthdiff.png",
            DepthDiffImage(v.changed[c], v.object_mask));
  if (ctx.features.enabled())
    for (std::size_t c = 0; c < nc; ++c)
      picture(columns[c].name + "_featseg", columns[c].label + ": feature segmentation before | after",
              stem + suffix(c) + "_featseg.png",
              FeatureSegImage(*v.before, v.after[c], v.object_mask, v.feature_seg_before, v.feature_seg[c]));
  ctx.view_images.push_back({{"view", cam.name}, {"images", std::move(pictures)}});
}

// Step 4b: the renders for external segmenters and the 8-bit depth pairs (METRICS.md §6) for
// re-scoring elsewhere.
void QueueExports(const EvalContext& ctx, const Camera& cam, const ViewRenders& v, PngJobs& jobs) {
  const std::string stem = SafeName(cam.name);
  if (ctx.o.export_renders) {
    jobs.emplace_back(ctx.out / "renders" / "before" / (stem + ".png"), RenderToRgb8(*v.before));
    for (std::size_t c = 0; c < ctx.columns.size(); ++c)
      jobs.emplace_back(ctx.out / "renders" / ctx.columns[c].name / (stem + ".png"), RenderToRgb8(v.after[c]));
  }
  if (!ctx.o.write_depth_pngs) return;
  const metrics::Gray8& g = v.object_gray;
  jobs.emplace_back(ctx.out / "masks" / (stem + ".png"), Image8{g.width, g.height, 1, g.pixels});
  for (std::size_t c = 0; c < ctx.columns.size(); ++c) {
    const fs::path d = ctx.out / "depth" / ctx.columns[c].name;
    const metrics::Depth8Pair& pair = v.pairs[c];
    jobs.emplace_back(d / "before" / (stem + ".png"), Image8{pair.before.width, pair.before.height, 1, pair.before.pixels});
    jobs.emplace_back(d / "after" / (stem + ".png"), Image8{pair.after.width, pair.after.height, 1, pair.after.pixels});
  }
}

// A view whose object mask is empty can still show part of the target (a thin or translucent part
// whose share of the render stays below the mask's 0.5): residual_gt's definition scores every view
// whose footprint has >= min_pixels pixels, so with labels (the renders exist already: the mask was
// rendered from them) it is scored here too; nothing else of the view is.
void ScoreGroundTruthOnly(EvalContext& ctx, const Camera& cam, std::unique_ptr<IncrementalRenderer>& renderer,
                          ViewRecord& view) {
  if (ctx.target.empty()) return;
  if (!renderer) renderer = std::make_unique<IncrementalRenderer>(ctx.scene, cam, ctx.render);
  const RenderOutput ideal = renderer->After(ctx.target);
  for (const EvalColumn& column : ctx.columns) {
    ColumnViewMetrics m;
    const RenderOutput after = renderer->After(column.removed);
    const metrics::ViewResidual gt = metrics::ComputeResidual(
        {ideal.width, ideal.height, renderer->before().rgb, after.rgb, ideal.rgb}, ctx.residual);
    if (gt.value) m.residual_gt = gt;
    view.columns.push_back(std::move(m));
  }
}

// Steps 1-4 for one camera; views without the object are counted and skipped (SPEC §6), but for
// residual_gt (above).
void EvaluateView(EvalContext& ctx, const Camera& cam, EvalResult& r) {
  ViewRecord view;
  view.name = cam.name;
  view.width = cam.width;
  view.height = cam.height;
  ViewRenders v;
  std::unique_ptr<IncrementalRenderer> renderer;
  if (!ObjectMaskOf(ctx, cam, r, v.object_gray, renderer)) {
    view.object_mask_missing = true;
    ++r.missing_object_masks;
  }
  v.object_mask = metrics::Binarize(v.object_gray, 0);
  view.object_pixels = v.object_mask.Count();
  if (view.object_pixels == 0) {
    if (!view.object_mask_missing) ++r.skipped_empty_object;
    if (!view.object_mask_missing) ScoreGroundTruthOnly(ctx, cam, renderer, view);
    r.views.push_back(std::move(view));
    return;
  }
  view.evaluated = true;
  ++r.evaluated;
  // Step 2: "before" in full (already done with --labels), each column incrementally from its cache.
  Timer t;
  if (!renderer) renderer = std::make_unique<IncrementalRenderer>(ctx.scene, cam, ctx.render);
  v.before = &renderer->before();
  for (const EvalColumn& column : ctx.columns) v.after.push_back(renderer->After(column.removed));
  if (!ctx.target.empty()) v.ideal = renderer->After(ctx.target);
  r.seconds_render += t.Seconds();
  t.Reset();
  ScoreView(ctx, cam, v, view);
  r.seconds_metrics += t.Seconds();
  t.Reset();
  PngJobs jobs;  // encoded in parallel: PNG compression dominates the I/O time
  if (ctx.o.write_images) QueuePictures(ctx, cam, v, jobs);
  QueueExports(ctx, cam, v, jobs);
  WritePngsParallel(jobs, ctx.o.render.num_threads);
  ctx.png_writes += jobs.size();
  r.seconds_io += t.Seconds();
  r.views.push_back(std::move(view));
}

// Mean and spread of each plug-in metric of column c over the evaluated views that define it.
std::vector<metrics::MeanStd> SummarizeViewMetrics(const std::vector<ViewRecord>& views, std::size_t c) {
  std::vector<metrics::MeanStd> out;
  for (std::size_t k = 0; k < ViewMetrics().size(); ++k) {
    std::vector<double> values;
    for (const ViewRecord& v : views)
      if (v.evaluated && v.columns[c].view_metrics[k]) values.push_back(*v.columns[c].view_metrics[k]);
    out.push_back(metrics::ComputeMeanStd(values));
  }
  return out;
}

// Summaries over the evaluated views, per column.
void SummarizeColumns(const EvalContext& ctx, EvalResult& r) {
  const std::size_t nc = ctx.columns.size();
  r.summaries.resize(nc);
  for (std::size_t c = 0; c < nc; ++c) {
    ColumnSummary& s = r.summaries[c];
    s.num_removed = std::size_t(std::count(ctx.columns[c].removed.begin(), ctx.columns[c].removed.end(), true));
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
    s.view_metrics = SummarizeViewMetrics(r.views, c);
    SummarizeResiduals(r.views, c, s);
    s.depth8 = metrics::SummarizeDepth(d8);
    s.depth_float = metrics::SummarizeDepth(df);
    s.collateral_psnr = metrics::ComputeMeanStd(psnr);
    if (ctx.run_semantic[c]) s.semantic = metrics::SummarizeSemantic(sem, ctx.o.semantic);
    if (ctx.features.enabled()) s.feature = metrics::SummarizeFeature(feat, ctx.o.semantic);
    if (ctx.run_sam[c]) {
      s.sim_sam = metrics::ComputeMeanStd(sim);
      s.sim_sam_missing = ctx.sam_missing[c];
    }
  }
  if (r.evaluated == 0)
    r.warnings.push_back("no view shows the object (all object masks empty or missing): every metric is 0");
  if (r.missing_object_masks)
    r.warnings.push_back(std::to_string(r.missing_object_masks) + " view(s) without an object mask in " +
                         ctx.object.masks_dir + " were excluded");
}

// report.json's "metrics": per column its summary (+ ground truth with labels, + added count).
json MetricsJson(const EvalContext& ctx, EvalResult& r) {
  const Scene& scene = ctx.scene;
  const bool with_gt = !ctx.object.labels.empty() && ctx.object.labels.size() == scene.size();
  const std::vector<float> opacity(scene.opacity_logits.data(), scene.opacity_logits.data() + scene.opacity_logits.size());
  json cols = json::array();
  for (std::size_t c = 0; c < ctx.columns.size(); ++c) {
    json j = ColumnSummaryJson(ctx.columns[c], r.summaries[c], ctx.o);
    AddResidualJson(r.views, c, r.summaries[c], j);
    if (with_gt) j["gt"] = ScoreRemoval(ctx.columns[c].removed, ctx.object.labels, ctx.object.object_id, opacity).ToJson();
    if (c > 0) j["added"] = std::size_t(std::count(ctx.added[c].begin(), ctx.added[c].end(), true));
    cols.push_back(std::move(j));
  }
  json skipped = json::array();
  for (const auto& s : r.skipped) skipped.push_back({{"metric", s.metric}, {"column", s.column}, {"reason", s.reason}});
  r.feature = ctx.features.ToJson();
  return {{"columns", cols},
          {"skipped", skipped},
          {"residuals", ResidualsInfoJson(ctx.headline, ctx.columns, !ctx.target.empty(), ctx.o.residual)},
          {"feature_segmentation", r.feature}};
}

// report.json's counts, metrics, warnings, outputs; the tables and metrics.csv beside it.
json WriteEvalFiles(const EvalContext& ctx, std::size_t num_views, EvalResult& r, const json* report_in) {
  json report = report_in ? *report_in : NewReport("eval");
  AddEvalParams(report, ctx.columns, ctx.object, ctx.o);
  report["counts"] = {{"num_gaussians", ctx.scene.size()},          {"views", num_views},
                      {"evaluated", r.evaluated},                   {"skipped_empty_object", r.skipped_empty_object},
                      {"missing_object_masks", r.missing_object_masks}, {"png_files", ctx.png_writes}};
  report["metrics"] = MetricsJson(ctx, r);
  json& warnings = report["warnings"];
  if (!warnings.is_array()) warnings = json::array();
  for (const auto& w : r.warnings) warnings.push_back(w);
  const Table table = TableFromResult(ctx.o.row_name, ctx.columns, r);
  WriteFileAtomically(ctx.out / "metrics.csv", MetricsCsv(ctx.columns, r));
  WriteFileAtomically(ctx.out / "table.md", TableMarkdown(table));
  WriteFileAtomically(ctx.out / "table.tex", TableLatex(table));
  r.outputs = {"report.json", "report.html", "metrics.csv", "table.md", "table.tex"};
  if (ctx.o.write_images) r.outputs.push_back("images/");
  if (ctx.o.write_depth_pngs) {
    r.outputs.push_back("masks/");
    r.outputs.push_back("depth/");
  }
  if (ctx.o.export_renders) r.outputs.push_back("renders/");
  report["outputs"] = r.outputs;
  return report;
}

void AddTimings(const EvalResult& r, json& report) {
  json& timings = report["timings_s"];
  if (!timings.is_object()) timings = json::object();
  timings["object_masks"] = r.seconds_object_masks;
  timings["feature_prepare"] = r.seconds_features;
  timings["render"] = r.seconds_render;
  timings["metrics"] = r.seconds_metrics;
  timings["io"] = r.seconds_io;
  timings["eval_total"] = r.seconds_total;
}

}  // namespace

EvalResult RunEval(const Scene& scene, const std::vector<Camera>& cameras, const std::vector<EvalColumn>& columns,
                   const ObjectSource& object, const EvalOptions& o, const json* report_in) {
  Timer total;
  Validate(scene, cameras, columns, object, o);
  EvalResult r;
  OutputSet staging(o.out_dir, EvalOutputSetOptions(o));  // --out checked before anything is computed
  if (!scene.source_path.empty())  // loaded from a file that may lack columns (in-code scenes have them all)
    for (auto& w : MissingRenderColumns(scene)) r.warnings.push_back(std::move(w));
  // Feature metrics: channels and prototypes once per scene; the renders composite the channels in
  // the RGB pass (al/eval/feature_eval.hpp).
  Timer feature_timer;
  EvalContext ctx(scene, columns, object, o, cameras);
  ctx.render = o.render;
  ctx.render.features = ctx.features.channels();
  r.seconds_features = feature_timer.Seconds();
  CheckEvalMemory(ctx, cameras);
  MarkGaussians(ctx);
  ctx.headline = r.headline = HeadlineResidual(!ctx.target.empty(), columns.size());
  ctx.residual = o.residual;
  ctx.residual.alpha_hit = o.float_depth.alpha_hit;
  PlanOptionalMetrics(ctx, r);
  ctx.out = staging.dir();
  ctx.images = ctx.out / "images";
  MakeOutputFolders(ctx);
  OpenSamLists(ctx);
  Progress progress("eval", cameras.size(), o.progress);
  for (std::size_t vi = 0; vi < cameras.size(); ++vi) {
    EvaluateView(ctx, cameras[vi], r);
    progress.Step(vi + 1);
  }
  progress.Finish();
  Timer t;
  SummarizeColumns(ctx, r);
  r.seconds_metrics += t.Seconds();
  t.Reset();
  json report = WriteEvalFiles(ctx, cameras.size(), r, report_in);
  r.seconds_io += t.Seconds();
  r.seconds_total = total.Seconds();
  AddTimings(r, report);
  WriteFileAtomically(ctx.out / "report.html", EvalReportHtml(report, ViewRecords(columns, r), ctx.view_images));
  r.report = staging.Commit(std::move(report));
  return r;
}

}  // namespace al::eval
