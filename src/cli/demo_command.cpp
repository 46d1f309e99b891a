// `al-refine demo --out DIR`: the whole job on a generated scene (README "./al demo"); the steps
// live in the library (al/demo/demo.hpp), this file parses, calls RunDemo and prints.
#include <cstdio>
#include <regex>

#include "al/core/error.hpp"
#include "al/demo/demo.hpp"
#include "src/cli/command.hpp"

namespace al::cli {

class DemoCommand : public Command {
 public:
  std::string Name() const override { return "demo"; }
  std::string Description() const override {
    return "Generate a synthetic room, refine its simulated GaussianCut removal with bk and cp, evaluate all "
           "three and print a summary (outputs under --out)";
  }
  void Setup(CLI::App& app) override {
    fixtures::SynthOptions& synth = options_.synth;
    app.add_option("--out", options_.out_dir, "Output folder")->capture_default_str();
    app.add_option("--gaussians", synth.num_gaussians, "Scene size")->check(CLI::Range(1000, 10000000))
        ->capture_default_str();
    app.add_option("--seed", synth.seed, "Random seed")->capture_default_str();
    app.add_option("--views", synth.num_views, "Camera views")->check(CLI::Range(1, 1000))->capture_default_str();
    app.add_option("--resolution", resolution_, "Image size WxH")->capture_default_str();
    app.add_flag("--quiet", quiet_, "No progress bars");
  }

  int Run() override {
    std::smatch m;
    static const std::regex re("^([0-9]+)x([0-9]+)$");
    if (!std::regex_match(resolution_, m, re)) throw Error("demo: --resolution must look like 320x240", ExitCode::kUsage);
    options_.synth.width = std::stoi(m[1].str());
    options_.synth.height = std::stoi(m[2].str());
    options_.progress = !quiet_;
    options_.on_step = [](const std::string& line) {
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    };
    const DemoResult r = RunDemo(options_);
    std::printf("%s", r.BriefReport().c_str());
    return 0;
  }

 private:
  DemoOptions options_;
  std::string resolution_ = "320x240";
  bool quiet_ = false;
};

AL_REGISTER_COMMAND(DemoCommand);

}  // namespace al::cli
