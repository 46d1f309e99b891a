#include "al/eval/output.hpp"

#include <omp.h>

#include "al/core/error.hpp"
#include "al/eval/eval.hpp"
#include "al/io/cameras.hpp"

namespace al::eval {

namespace fs = std::filesystem;

OutputSetOptions EvalOutputSetOptions(const EvalOptions& o) {
  OutputSetOptions so;
  so.command = "eval";
  for (const auto& p : o.input_paths) so.inputs.push_back(p);
  for (const auto& p : {o.seg_before_dir, o.sam_before_dir}) so.inputs.push_back(p);
  so.planned = {"report.json", "report.html", "metrics.csv", "table.md", "table.tex"};
  if (o.write_images) so.planned.push_back("images");
  if (o.export_renders) so.planned.push_back("renders");
  if (o.write_depth_pngs) {
    so.planned.push_back("masks");
    so.planned.push_back("depth");
  }
  return so;
}

void WritePngsParallel(const std::vector<std::pair<fs::path, Image8>>& jobs, int num_threads) {
  // Exceptions must not leave an OpenMP region: collect them per job.
  std::vector<std::string> errors(jobs.size());
  const int threads = num_threads > 0 ? num_threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(jobs.size()); ++i) {
    try {
      WritePng8(jobs[std::size_t(i)].first.string(), jobs[std::size_t(i)].second);
    } catch (const std::exception& e) {
      errors[std::size_t(i)] = e.what();
    }
  }
  for (const auto& e : errors)
    if (!e.empty()) throw Error(e);
}

std::string SafeName(std::string name) { return SafeFileName(std::move(name)); }

}  // namespace al::eval
