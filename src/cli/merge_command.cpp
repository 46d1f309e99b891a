// `al-refine merge SHARD_DIR... --out DIR`: combine the outputs of sweep shards (dedupe by point
// id, canonical order, results.csv, charts, report.json). Library: al/refine/sweep.hpp.
#include <iostream>

#include "al/refine/sweep.hpp"
#include "src/cli/command.hpp"

namespace al::cli {

class MergeCommand : public Command {
 public:
  std::string Name() const override { return "merge"; }
  std::string Description() const override {
    return "Combine sweep shard directories into one sweep output (results.jsonl/.csv, charts, report.json)";
  }
  void Setup(CLI::App& app) override {
    app.add_option("dirs", dirs_, "Shard output directories (each with results.jsonl)")->required();
    app.add_option("--out", out_, "Output directory")->required();
  }

  int Run() override {
    const MergeResult r = MergeSweeps(dirs_, out_);
    for (const auto& w : r.warnings) std::cerr << "warning: " << w << "\n";
    std::cout << "merged " << dirs_.size() << " directories: " << r.records << " records (" << r.duplicates
              << " duplicates, " << r.conflicts << " conflicts)\nwrote " << out_ << "/results.jsonl, results.csv, "
              << "report.json\n";
    return 0;
  }

 private:
  std::vector<std::string> dirs_;
  std::string out_;
};

AL_REGISTER_COMMAND(MergeCommand);

}  // namespace al::cli
