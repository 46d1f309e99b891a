// `al-refine merge SHARD_DIR... --out DIR`: combine the outputs of sweep shards after checking that
// they are the shards of one sweep and that none is missing (library: al/refine/sweep.hpp).
#include <iostream>

#include "al/refine/sweep.hpp"
#include "src/cli/command.hpp"

namespace al::cli {

class MergeCommand : public Command {
 public:
  std::string Name() const override { return "merge"; }
  std::string Description() const override {
    return "Combine the shard folders of one sweep into one sweep output (results.jsonl/.csv, charts, "
           "report.json); refuses folders of different sweeps and, unless --allow-partial, an incomplete set";
  }
  void Setup(CLI::App& app) override {
    app.add_option("dirs", o_.shard_dirs, "Shard output folders (each with shard.json and results.jsonl)")->required();
    app.add_option("--out", o_.out_dir, "Output folder (required unless --check)");
    app.add_flag("--allow-partial", o_.allow_partial,
                 "Merge even when shards or points are missing (report.json then says complete: false)");
    app.add_flag("--check", o_.check_only,
                 "Only check the set: print missing and incomplete shards (\"incomplete shards: 1 4\"), write "
                 "nothing; exit 0 when complete, 2 when not");
  }

  int Run() override {
    const MergeResult r = MergeSweeps(o_);
    std::cout << r.BriefReport();
    for (const auto& w : r.warnings) std::cerr << "warning: " << w << "\n";
    if (r.written)
      std::cout << "wrote " << o_.out_dir << "/results.jsonl, results.csv, report.json"
                << (r.complete ? "" : " (partial: report.json says complete: false)") << "\n";
    if (r.exit_code != 0) std::cerr << "al-refine merge: error: " << r.message << "\n";
    return r.exit_code;
  }

 private:
  MergeOptions o_;
};

AL_REGISTER_COMMAND(MergeCommand);

}  // namespace al::cli
