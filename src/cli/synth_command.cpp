// `al-refine synth`: a synthetic scene with ground truth and the four method simulators (SPEC §7).
#include <cstdio>
#include <iostream>
#include <regex>

#include "al/core/error.hpp"
#include "al/core/progress.hpp"
#include "al/fixtures/synth.hpp"
#include "src/cli/command.hpp"

namespace al::cli {

class SynthCommand : public Command {
 public:
  std::string Name() const override { return "synth"; }
  std::string Description() const override {
    return "Generate a synthetic scene with ground-truth labels, masks and simulated removals";
  }
  void Setup(CLI::App& app) override {
    app.add_option("--preset", options_.preset, "room | counter | garden")->check(CLI::IsMember({"room", "counter", "garden"}));
    app.add_option("--gaussians", options_.num_gaussians, "exact number of Gaussians (>= 1000)")->capture_default_str();
    app.add_option("--seed", options_.seed, "random seed (results are deterministic in it)")->capture_default_str();
    app.add_option("--feature-dim", options_.feature_dim, "semantic feature dimension (1..512)")->capture_default_str();
    app.add_option("--views", options_.num_views, "number of orbit cameras")->capture_default_str();
    app.add_option("--resolution", resolution_, "image size WxH")->capture_default_str();
    app.add_option("--sh-degree", options_.sh_degree, "SH degree 0..3")->capture_default_str();
    app.add_option("--threads", options_.num_threads, "threads (0 = all; output does not depend on it)");
    app.add_flag("--no-masks", no_masks_, "skip masks (and the SAGS simulator, which needs them)");
    app.add_flag("--quiet", quiet_, "no progress output");
    app.add_option("--out", out_, "output directory")->required();
  }
  int Run() override {
    std::smatch m;
    static const std::regex re("^([0-9]+)x([0-9]+)$");
    if (!std::regex_match(resolution_, m, re)) throw Error("synth: --resolution must look like 320x240", ExitCode::kUsage);
    options_.width = std::stoi(m[1].str());
    options_.height = std::stoi(m[2].str());
    options_.compute_masks = !no_masks_;
    std::unique_ptr<Progress> bar;
    std::string stage;
    if (!quiet_) {
      options_.progress = [&](const std::string& s, double f) {
        if (s != stage) {
          if (bar) bar->Finish();
          bar = std::make_unique<Progress>("synth " + s, 1000, options_.num_gaussians >= 200000);
          stage = s;
        }
        bar->Step(std::size_t(f * 1000));
      };
    }
    const fixtures::SynthFolderResult r = fixtures::SynthesizeToFolder(options_, out_);
    if (bar) bar->Finish();
    const fixtures::SynthScene& synth = r.synth;
    const nlohmann::json& report = r.report;
    std::printf("synth: %s, %zu Gaussians, target %d (%s, %zu Gaussians) -> %s\n", options_.preset.c_str(),
                synth.labels.size(), synth.target_id, synth.target_name.c_str(),
                synth.objects[std::size_t(synth.target_id)].count, out_.c_str());
    for (const auto& [name, sc] : report["simulators"].items())
      std::printf("  %-5s precision %.3f  recall %.3f  F1 %.3f\n", name.c_str(), sc["precision"].get<double>(),
                  sc["recall"].get<double>(), sc["f1"].get<double>());
    return 0;
  }

 private:
  fixtures::SynthOptions options_;
  std::string resolution_ = "320x240";
  std::string out_;
  bool no_masks_ = false;
  bool quiet_ = false;
};

AL_REGISTER_COMMAND(SynthCommand);

}  // namespace al::cli
