// `al-refine refine` (also the default subcommand): flags -> RefineOptions -> RunRefine.
#include <iostream>

#include "al/core/error.hpp"
#include "al/refine/refine.hpp"
#include "src/cli/command.hpp"
#include "src/cli/refine_flags.hpp"

namespace al::cli {

class RefineCommand : public Command {
 public:
  std::string Name() const override { return "refine"; }
  std::string Description() const override {
    return "Refine a removal: candidates around the removed set, kNN + semantic graph, solver, "
           "threshold; writes refined.npy/.txt, added.txt, remaining.ply, report.json";
  }
  void Setup(CLI::App& app) override {
    AddInputFlags(app, flags_);
    AddGraphFlags(app, flags_);
    AddSolverFlags(app, flags_);
    AddDecisionFlags(app, flags_);
    app.add_option("--out", flags_.options.out_dir, "Output directory")->required();
    app.add_option("--export-problem", flags_.options.export_problem_dir,
                   "Also write the solvers' exact problem and p as .npy files into this directory "
                   "(first_edge, adj_vertices, edge_weights, y, node_weights, node_ids, params.json, p)");
    app.add_flag("--quiet", quiet_, "No progress lines");
  }

  int Run() override {
    RefineOptions o = ToRefineOptions(flags_);
    if (!quiet_)
      o.on_stage = [](const std::string& stage, double s) {
        if (s > 1.0) std::cerr << "refine  " << stage << "  " << s << " s\n";
      };
    const RefineResult r = RunRefine(o);
    const auto& c = r.report["counts"];
    std::cout << "nodes " << c["candidates"] << ", edges " << c["edges"] << ", removed "
              << c["removed_input"] << " -> " << c["refined"] << "\n";
    if (r.report.contains("gt"))
      std::cout << "ground truth F1 " << r.report["gt"]["before"]["f1"] << " -> "
                << r.report["gt"]["after"]["f1"] << "\n";
    (r.exit_code == 0 ? std::cout : std::cerr) << r.message << "\n";
    std::cout << "wrote " << o.out_dir << "/report.json\n";
    return r.exit_code;
  }

 private:
  RefineFlags flags_;
  bool quiet_ = false;
};

AL_REGISTER_COMMAND(RefineCommand);

}  // namespace al::cli
