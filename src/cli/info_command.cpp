// `al-refine info --scene S [--json] [--features PREFIX|auto|none] [--out DIR]`: what a scene holds.
#include <iostream>

#include "al/core/error.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/io/ply.hpp"
#include "src/cli/command.hpp"

namespace al::cli {

class InfoCommand : public Command {
 public:
  std::string Name() const override { return "info"; }
  std::string Description() const override {
    return "Print what a scene holds: size, SH degree, features, bounding box, scale/opacity statistics, "
           "non-finite values";
  }
  void Setup(CLI::App& app) override {
    app.add_option("--scene", scene_, "Scene file (.ply or .splat)")->required();
    app.add_flag("--json", json_, "Print one JSON object to stdout instead of text");
    app.add_option("--features", features_, "Feature columns: auto, none or an explicit PREFIX")
        ->default_val("auto");
    app.add_option("--out", out_, "Also write DIR/report.json");
  }
  int Run() override {
    PlyReadOptions options;
    options.feature_prefix = features_;
    options.require_scales = false;  // info describes any PLY, even a position-only subset
    Timer timer;
    const Scene scene = ReadScene(scene_, options);
    const double load_s = timer.Seconds();
    const SceneSummary stats = SummarizeScene(scene);
    const nlohmann::json summary = SummaryToJson(stats);
    if (json_) {
      std::cout << summary.dump() << "\n";
    } else {
      std::cout << scene_ << "\n" << SummaryToText(stats);
    }
    if (!out_.empty()) {
      nlohmann::json report = NewReport("info");
      report["params"] = {{"scene", scene_}, {"features", features_}};
      AddInputFile(report, "scene", scene_);
      report["counts"] = {{"num_gaussians", scene.size()}};
      report["scene"] = summary;
      report["timings_s"] = {{"load", load_s}};
      WriteReport(out_, report);
    }
    return 0;
  }

 private:
  std::string scene_, features_ = "auto", out_;
  bool json_ = false;
};

AL_REGISTER_COMMAND(InfoCommand);

}  // namespace al::cli
