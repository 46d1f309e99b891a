// `al-refine sweep`: refine settings over a grid (and a manifest of scenes) -> results.jsonl,
// results.csv, charts, report.json (library: al/refine/sweep.hpp).
#include <cstdio>
#include <iostream>

#include "al/core/error.hpp"
#include "al/refine/sweep.hpp"
#include "src/cli/command.hpp"
#include "src/cli/warnings.hpp"
#include "src/cli/refine_flags.hpp"

namespace al::cli {

class SweepCommand : public Command {
 public:
  std::string Name() const override { return "sweep"; }
  std::string Description() const override {
    return "Run refine over a parameter grid (one graph per k/delta/hops, reused across lambda, solvers, "
           "thresholds); writes results.jsonl (resumable), results.csv, pareto.png, heat maps, report.json";
  }
  void Setup(CLI::App& app) override {
    AddInputFlags(app, flags_);
    AddGraphFlags(app, flags_);
    AddSolverFlags(app, flags_);
    AddDecisionFlags(app, flags_);
    // With --manifest the scenes come from the manifest.
    app.get_option("--scene")->required(false);
    app.get_option("--solver")->description("Solver when the grid has no solver axis");
    app.get_option("--solver-options")
        ->description("JSON object of options per solver, e.g. '{\"cp\": {\"max_iterations\": 20}}'");
    app.add_option("--grid", grid_, "Grid: \"k=4,6,10;delta=0.8,1.0;lambda=0.5,1,2;solver=bk,cp\" "
                   "(keys k, delta, hops, radius_scale, lambda, solver, threshold; others: the flags' values)")
        ->required();
    app.add_option("--manifest", manifest_, "JSON list of scenes {name, scene, removed, removed_is?, method?, "
                   "features?, labels?, object_id?, cameras?, object_masks?} (paths relative to the manifest)");
    app.add_option("--cameras", cameras_, "Cameras (single-scene sweeps): evaluator metrics per point "
                   "(acc_delta_depth, collateral damage); the object from --object-masks, else --labels");
    app.add_option("--object-masks", object_masks_, "Folder of object mask PNGs joined to the cameras by name");
    app.add_option("--views", views_, "Views evaluated per point: all, or comma-separated names")->default_val("all");
    app.add_option("--name", name_, "Scene name in the records (single-scene sweeps)")->default_val("scene");
    app.add_option("--shard", shard_, "Run only slice i of n (0-based, e.g. 2/8) of the grid x scenes");
    app.add_option("--out", out_, "Output directory (rerunning skips the points already in results.jsonl)")->required();
    app.add_flag("--quiet", quiet_, "No progress lines");
    app.add_flag("--dry-run", o_.dry_run, "Check the flags, grid, every scene's inputs and --out (a folder of "
                 "another sweep is refused); print the point counts; run and write nothing");
  }

  int Run() override {
    const RefineOptions base = ToRefineOptions(flags_);
    SweepOptions& o = o_;
    o.out_dir = out_;
    if (!manifest_.empty()) {
      if (!base.scene.empty() || !base.removed.empty() || !cameras_.empty() || !object_masks_.empty())
        throw Error("give either --manifest or --scene/--removed/--cameras/--object-masks, not both", ExitCode::kUsage);
      o.scenes = ReadSweepManifest(manifest_, base);
    } else {
      if (base.scene.empty()) throw Error("--scene (or --manifest) is required", ExitCode::kUsage);
      if (name_.empty() || name_.find('|') != std::string::npos)
        throw Error("--name: must be non-empty and without '|'", ExitCode::kUsage);
      if (cameras_.empty() && !object_masks_.empty()) throw Error("--object-masks needs --cameras", ExitCode::kUsage);
      o.scenes.push_back({name_, base, cameras_, object_masks_});
    }
    o.grid = ParseSweepGrid(grid_, base);
    if (!shard_.empty()) o.shard = ParseShard(shard_);
    o.solver_options = base.solver_options;
    o.eval_views = views_;
    if (!quiet_) o.on_point = PrintProgress;
    const SweepResult r = RunSweep(o);
    if (o.dry_run) {
      std::cout << "sweep: dry run: " << r.total << " points, " << r.in_shard << " in shard " << o.shard.ToString()
                << "; nothing run or written\n";
      return 0;
    }
    std::cout << "sweep: " << r.ran << " points run, " << r.already_done << " already done, " << r.in_shard
              << " in shard " << o.shard.ToString() << " of " << r.total << " (" << r.graphs_built
              << " graphs built, " << r.empty_graphs << " empty graphs)\n";
    for (const auto& c : r.report["outputs"]["charts"]) std::cout << "chart " << out_ << "/" << c.get<std::string>() << "\n";
    PrintReportWarnings(r.report);
    if (o.shard.count > 1) std::cout << "charts: drawn by `al-refine merge` over all shards\n";
    std::cout << "wrote " << out_ << "/results.jsonl, results.csv, report.json\n";
    return 0;
  }

 private:
  // One line per point: "sweep  point 3/36  scene|k=4|...  0.42 s  F1 0.812 -> 0.903".
  static void PrintProgress(const SweepProgress& p) {
    std::string line = "sweep  point " + std::to_string(p.position) + "/" + std::to_string(p.count) + "  " + p.id;
    if (!p.record) {
      std::cerr << line << "  (done earlier, skipped)\n";
      return;
    }
    const nlohmann::json& r = *p.record;
    char buf[128];
    std::snprintf(buf, sizeof buf, "  %.3f s", r["seconds"].value("point", 0.0));
    line += buf;
    if (r.contains("gt")) {
      std::snprintf(buf, sizeof buf, "  F1 %.4f -> %.4f", r["gt"]["before"]["f1"].get<double>(),
                    r["gt"]["after"]["f1"].get<double>());
      line += buf;
    }
    if (r.contains("eval")) {
      std::snprintf(buf, sizeof buf, "  acc_dd %.3f  collateral %.4f", r["eval"]["acc_delta_depth"].get<double>(),
                    r["eval"]["collateral_depth"].get<double>());
      line += buf;
    }
    if (r["status"] != "ok") line += "  " + r["status"].get<std::string>();
    std::cerr << line << std::endl;
  }

  RefineFlags flags_;
  SweepOptions o_;
  std::string grid_, manifest_, name_ = "scene", shard_, out_, cameras_, object_masks_, views_ = "all";
  bool quiet_ = false;
};

AL_REGISTER_COMMAND(SweepCommand);

}  // namespace al::cli
