// Interim `al-refine demo [--out DIR]`: writes a small deterministic generated scene with WritePly
// and prints the summary of the re-read file. (To be replaced by the full pipeline demo.)
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>

#include "al/core/atomic_file.hpp"
#include "al/core/report.hpp"
#include "al/io/ply.hpp"
#include "src/cli/command.hpp"

namespace al::cli {
namespace {

// SplitMix64: fully specified, so the scene is identical on every platform and standard library
// (std:: distributions are implementation-defined).
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t Next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  float Uniform(float lo, float hi) { return lo + (hi - lo) * static_cast<float>((Next() >> 40) * 0x1.0p-24); }
};

// Two clusters ("table" and "object on it") with SH degree 1 and 8-D one-hot-ish semantic features.
Scene DemoScene(std::size_t n, std::uint64_t seed) {
  constexpr int kDim = 8;
  SplitMix64 rng{seed};
  Scene s;
  s.sh_degree = 1;
  s.means.resize(n, 3);
  s.log_scales.resize(n, 3);
  s.rotations.resize(n, 4);
  s.opacity_logits.resize(n);
  s.sh.resize(n, 12);
  s.features.resize(n, kDim);
  s.feature_prefix = "semantic_";
  s.has_opacity = s.has_scales = s.has_rotations = s.has_f_dc = true;
  s.source_format = "generated";
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(n); ++i) {
    const bool object = i % 4 == 0;
    if (object) {
      s.means.row(i) << rng.Uniform(-0.3f, 0.3f), rng.Uniform(0.0f, 0.5f), rng.Uniform(-0.3f, 0.3f);
    } else {
      s.means.row(i) << rng.Uniform(-2.0f, 2.0f), rng.Uniform(-0.05f, 0.0f), rng.Uniform(-2.0f, 2.0f);
    }
    for (int c = 0; c < 3; ++c) s.log_scales(i, c) = std::log(rng.Uniform(0.01f, 0.05f));
    float q[4], norm = 0;
    for (float& v : q) { v = rng.Uniform(-1.0f, 1.0f); norm += v * v; }
    norm = std::sqrt(norm) + 1e-6f;
    for (int c = 0; c < 4; ++c) s.rotations(i, c) = q[c] / norm;
    s.opacity_logits(i) = rng.Uniform(-1.0f, 4.0f);
    for (int k = 0; k < 12; ++k) s.sh(i, k) = k < 3 ? rng.Uniform(-1.0f, 1.0f) : rng.Uniform(-0.1f, 0.1f);
    for (int d = 0; d < kDim; ++d) s.features(i, d) = rng.Uniform(-0.1f, 0.1f) + ((d == (object ? 1 : 0)) ? 1.0f : 0.0f);
  }
  return s;
}

}  // namespace

class DemoCommand : public Command {
 public:
  std::string Name() const override { return "demo"; }
  std::string Description() const override {
    return "Write a small deterministic generated scene (2,000 Gaussians) and print its summary";
  }
  void Setup(CLI::App& app) override {
    app.add_option("--out", out_, "Output folder")->default_val("demo_out");
    app.add_option("--gaussians", gaussians_, "Number of Gaussians")->default_val(2000)->check(CLI::Range(1, 10000000));
    app.add_option("--seed", seed_, "Random seed")->default_val(1);
  }
  int Run() override {
    EnsureDirectory(out_);
    const std::filesystem::path ply = std::filesystem::path(out_) / "scene.ply";
    WritePly(ply.string(), DemoScene(static_cast<std::size_t>(gaussians_), seed_));
    const Scene reread = ReadPly(ply.string());
    const SceneSummary stats = SummarizeScene(reread);
    std::cout << "demo scene written to " << ply.string() << "\n" << SummaryToText(stats);
    nlohmann::json report = NewReport("demo");
    report["params"] = {{"out", out_}, {"gaussians", gaussians_}, {"seed", seed_}};
    report["counts"] = {{"num_gaussians", reread.size()}};
    report["scene"] = SummaryToJson(stats);
    report["outputs"] = {{"scene", ply.string()}};
    WriteReport(out_, report);
    return 0;
  }

 private:
  std::string out_ = "demo_out";
  long gaussians_ = 2000;
  std::uint64_t seed_ = 1;
};

AL_REGISTER_COMMAND(DemoCommand);

}  // namespace al::cli
