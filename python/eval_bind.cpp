// al_refine.evaluate: the evaluator (RunEval) on in-memory sets; summary and per-view metrics as
// records that pandas.DataFrame takes directly.
#include <filesystem>
#include <random>

#include <pybind11/stl.h>

#include "al/core/error.hpp"
#include "al/eval/eval.hpp"
#include "al/eval/feature_eval.hpp"
#include "al/eval/records.hpp"
#include "python/common.hpp"
#include "python/options.hpp"

namespace al::python {
namespace {

namespace fs = std::filesystem;

// Columns: the removal method's set first, then each refinement (a mask, or {name: mask}).
std::vector<eval::EvalColumn> Columns(const py::array& removed, const py::object& refined, const std::string& label,
                                      std::size_t n) {
  std::vector<eval::EvalColumn> columns = {{"after", label, MaskFromPython(removed, n, "removed"), "", ""}};
  if (refined.is_none()) return columns;
  if (py::isinstance<py::dict>(refined)) {
    for (const auto& [key, value] : refined.cast<py::dict>()) {
      const std::string name = py::str(key).cast<std::string>();
      columns.push_back({name, label + "+" + name, MaskFromPython(value.cast<py::array>(), n, name), "", ""});
    }
  } else {
    columns.push_back({"refined", label + "+refined", MaskFromPython(refined.cast<py::array>(), n, "refined"), "", ""});
  }
  return columns;
}

// A scratch output folder when the caller wants no files (RunEval always writes its outputs).
struct ScratchDir {
  fs::path path;
  ScratchDir() {
    std::random_device rd;
    path = fs::temp_directory_path() / ("al_refine_eval_" + std::to_string(rd()) + std::to_string(rd()));
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// EvalOptions has no options table yet: the fields bound here by name are out, row_name, images,
// background, sh_degree, threads; a table added later is applied by TakeTableOptions. The feature
// metrics' options have tables (feature_metrics, feature_min_sim, ...: the CLI's --feature-* flags).
eval::EvalOptions EvalOptionsFrom(const std::string& out, const std::string& row_name, bool images,
                                  const std::vector<float>& background, int sh_degree, int threads, py::dict kwargs) {
  eval::EvalOptions o;
  o.out_dir = out;
  o.row_name = row_name;
  o.write_images = images;
  o.write_depth_pngs = images;
  o.progress = false;
  if (background.size() != 3) throw Error("evaluate: background must be 3 numbers", ExitCode::kUsage);
  o.render.background = Eigen::Vector3f(background[0], background[1], background[2]);
  o.render.max_sh_degree = sh_degree;
  o.render.num_threads = threads;
  TakeTableOptions(o, kwargs);
  TakeOptions(eval::FeatureEvalOptions::Table(), o.feature, kwargs);
  TakeOptions(FeatureFieldOptions::Table(), o.feature.field, kwargs);
  TakeOptions(metrics::FeatureSegOptions::Table(), o.feature.segmentation, kwargs);
  TakeOptions(metrics::ResidualOptions::Table(), o.residual, kwargs);
  for (const auto& [key, value] : kwargs)
    throw Error("evaluate: unknown option '" + py::str(key).cast<std::string>() +
                    "' (out, row_name, images, background, sh_degree, threads, the feature_* and residual options)",
                ExitCode::kUsage);
  return o;
}

py::dict Evaluate(const PyScene& scene, const py::object& cameras, const py::array& removed, const py::object& refined,
                  const py::object& labels, const py::object& object_id, const py::object& object_masks,
                  const std::string& label, const py::object& out, const std::string& row_name, bool images,
                  const std::vector<float>& background, int sh_degree, int threads, const py::kwargs& kwargs) {
  const std::size_t n = scene.scene->size();
  ScratchDir scratch;
  const std::string out_dir = out.is_none() ? scratch.path.string() : py::str(out).cast<std::string>();
  const eval::EvalOptions o = EvalOptionsFrom(out_dir, row_name, images && !out.is_none(), background, sh_degree,
                                              threads, py::dict(kwargs));
  const std::vector<eval::EvalColumn> columns = Columns(removed, refined, label, n);
  eval::ObjectSource object;
  if (!object_masks.is_none()) object.masks_dir = py::str(object_masks).cast<std::string>();
  if (!labels.is_none()) {
    object.labels = LabelsFrom(labels, "evaluate: labels");
    if (object_id.is_none()) throw Error("evaluate: labels need object_id", ExitCode::kUsage);
    object.object_id = ObjectIdFrom(object_id, object.labels, "evaluate");
  }
  if (object.masks_dir.empty() && object.labels.empty())
    throw Error("evaluate: give object_masks (a folder of VIEW.png) or labels and object_id", ExitCode::kUsage);
  const std::vector<Camera> views = CameraList(cameras);
  eval::EvalResult r;
  nlohmann::json view_records;
  {
    py::gil_scoped_release release;
    r = eval::RunEval(*scene.scene, views, columns, object, o);
    view_records = eval::ViewRecords(columns, r);
  }
  py::dict result;
  result["summary"] = FromJson(eval::ColumnRecords(r.report));
  result["views"] = FromJson(view_records);
  result["report"] = FromJson(r.report);
  result["out"] = out.is_none() ? py::object(py::none()) : py::object(py::str(out_dir));
  return result;
}

std::string EvaluateDoc() {
  std::string doc = R"(evaluate(scene, cameras, removed, refined=None, *, labels=None, object_id=None, object_masks=None,
         label="removal", out=None, row_name="scene", images=True, background=(0, 0, 0), sh_degree=3,
         threads=0, **options)

The evaluator of `al-refine eval` (docs/eval.md): renders every view before the removal, after it
and after each refinement, and computes what is left of the object (residual_gt with labels,
residual_est against the first refinement, residual_px from the object masks: the summary's
residual_*.mean, 0 = gone, 1 = untouched), acc_delta_depth (8-bit and float), collateral damage, the
feature metrics when the scene has semantic features (IoU_drop_feat, acc_seg_feat, residual_feat:
the summary's feature.* fields) and, with labels, the scores against the ground truth. removed:
the method's set (bool mask or indices); refined: one refined set, or {name: set}. The object per
view: labels + object_id (rendered, share >= 0.5) or object_masks (a folder of VIEW.png). out: a
folder for the CLI's outputs (report.json, report.html, metrics.csv, tables, images); None:
nothing is kept. The GIL is released while rendering.

Returns {"summary": one flat record per column, "views": one record per view (the metrics.csv
columns), "report": the report.json dict, "out": the folder or None}; pandas.DataFrame(result[
"summary"]) and pandas.DataFrame(result["views"]) give the tables.

)";
  doc += OptionsDoc(eval::FeatureEvalOptions::Table()) + OptionsDoc(FeatureFieldOptions::Table()) +
         OptionsDoc(metrics::FeatureSegOptions::Table()) + OptionsDoc(metrics::ResidualOptions::Table());
  return doc;
}

}  // namespace

void BindEval(py::module_& m) {
  static const std::string doc = EvaluateDoc();
  m.def("evaluate", &Evaluate, py::arg("scene"), py::arg("cameras"), py::arg("removed"),
        py::arg("refined") = py::none(), py::kw_only(), py::arg("labels") = py::none(),
        py::arg("object_id") = py::none(), py::arg("object_masks") = py::none(), py::arg("label") = "removal",
        py::arg("out") = py::none(), py::arg("row_name") = "scene", py::arg("images") = true,
        py::arg("background") = std::vector<float>{0, 0, 0}, py::arg("sh_degree") = 3, py::arg("threads") = 0,
        doc.c_str());
}

}  // namespace al::python
