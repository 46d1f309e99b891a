// `al-refine info --scene S [--json] [--features PREFIX|auto|none] [--out DIR]`: what a scene holds.
// `al-refine info --verify DIR`: whether DIR holds the complete output set its report.json lists.
#include <iostream>
#include <optional>

#include "al/core/error.hpp"
#include "al/core/output_set.hpp"
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
           "non-finite values; or (--verify DIR) whether an output folder is complete";
  }
  void Setup(CLI::App& app) override {
    app.add_option("--scene", scene_, "Scene file (.ply or .splat)");
    app.add_flag("--json", json_, "Print one JSON object to stdout instead of text");
    app.add_option("--features", features_, "Feature columns: auto, none or an explicit PREFIX")
        ->default_val("auto");
    app.add_option("--out", out_, "Also write DIR/report.json");
    app.add_option("--verify", verify_, "Check an output folder against the manifest of its report.json: "
                   "complete (exit 0), extended by a resumable journal (0), or incomplete / not a set (2)");
  }
  int Run() override {
    if (!verify_.empty()) return Verify();
    if (scene_.empty()) throw Error("info: give --scene FILE or --verify DIR", ExitCode::kUsage);
    std::optional<OutputSet> set;
    if (!out_.empty()) set.emplace(out_, OutputSetOptions("info", {scene_}, {"report.json"}));
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
    if (set) {
      nlohmann::json report = NewReport("info");
      report["params"] = {{"scene", scene_}, {"features", features_}};
      AddInputFile(report, "scene", scene_);
      report["counts"] = {{"num_gaussians", scene.size()}};
      report["scene"] = summary;
      report["timings_s"] = {{"load", load_s}};
      set->Commit(report);
    }
    return 0;
  }

 private:
  int Verify() const {
    const OutputSetStatus s = VerifyOutputSet(verify_);
    if (json_) {
      std::cout << s.ToJson().dump() << "\n";
    } else {
      std::cout << verify_ << ": " << s.state << (s.command.empty() ? "" : " (" + s.command + ")") << ", " << s.files
                << " files in the manifest\n";
      for (const auto& p : s.problems) std::cout << "  " << p << "\n";
      for (const auto& n : s.notes) std::cout << "  note: " << n << "\n";
    }
    const bool ok = s.state == "complete" || s.state == "extended";
    return ok ? 0 : static_cast<int>(ExitCode::kBadInput);
  }

  std::string scene_, features_ = "auto", out_, verify_;
  bool json_ = false;
};

AL_REGISTER_COMMAND(InfoCommand);

}  // namespace al::cli
