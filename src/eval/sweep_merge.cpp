// MergeSweeps (al/refine/sweep.hpp): shard outputs -> one sweep output (dedupe by id, canonical
// order, CSV, charts, report).
#include <filesystem>
#include <map>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/output_set.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/refine/sweep.hpp"

namespace al {

namespace fs = std::filesystem;

MergeResult MergeSweeps(const std::vector<std::string>& shard_dirs, const std::string& out_dir) {
  Timer timer;
  if (shard_dirs.empty()) throw Error("merge: no shard directory given", ExitCode::kUsage);
  if (out_dir.empty()) throw Error("--out is required", ExitCode::kUsage);
  std::error_code ec;
  for (const auto& d : shard_dirs) {
    if (!fs::is_regular_file(fs::path(d) / "results.jsonl"))
      throw Error(d + ": no results.jsonl (not a sweep output directory)", ExitCode::kBadInput);
    if (fs::equivalent(fs::path(d), fs::path(out_dir), ec))
      throw Error(d + ": --out must differ from the shard directories", ExitCode::kUsage);
  }

  OutputSetOptions so;
  so.command = "merge";
  so.inputs.assign(shard_dirs.begin(), shard_dirs.end());
  so.planned = {"results.jsonl", "results.csv", "report.json"};
  OutputSet set(out_dir, so);
  const fs::path out_jsonl = set.dir() / "results.jsonl";
  MergeResult result;
  nlohmann::json report = NewReport("merge");
  std::map<std::string, std::size_t> index;  // id -> position in records
  std::vector<nlohmann::json> records;
  nlohmann::json per_shard = nlohmann::json::array();
  for (const auto& d : shard_dirs) {
    const std::string path = (fs::path(d) / "results.jsonl").string();
    AddInputFile(report, "shard " + d, path);
    JsonlContents c = ReadResultsJsonl(path);
    if (c.truncated_tail)
      result.warnings.push_back(path + ": ends in a truncated line (a killed shard); rerun that shard to complete it");
    per_shard.push_back({{"dir", d}, {"records", c.records.size()}, {"truncated_tail", c.truncated_tail}});
    for (auto& r : c.records) {
      const std::string id = r["id"].get<std::string>();
      const auto it = index.find(id);
      if (it == index.end()) {
        index[id] = records.size();
        records.push_back(std::move(r));
        continue;
      }
      ++result.duplicates;
      if (RecordWithoutTimings(records[it->second]) != RecordWithoutTimings(r)) {
        ++result.conflicts;
        result.warnings.push_back(id + ": results differ between shards (kept the first, from an earlier directory)");
      }
    }
  }
  SortRecords(records);
  WriteFileAtomically(out_jsonl, [&](std::ostream& os) {
    for (const auto& r : records) os << r.dump() << '\n';
  });
  const nlohmann::json summaries = WriteSweepSummaries(set.dir().string(), records);
  for (const auto& s : summaries["skipped_charts"])
    result.warnings.push_back("chart " + s["name"].get<std::string>() + " skipped: " + s["reason"].get<std::string>());
  result.records = records.size();
  report["params"] = {{"shards", shard_dirs}, {"out", out_dir}};
  report["shards"] = per_shard;
  report["outputs"] = summaries;
  report["counts"] = {{"records", result.records}, {"duplicates", result.duplicates}, {"conflicts", result.conflicts}};
  for (const auto& w : result.warnings) report["warnings"].push_back(w);
  report["timings_s"] = {{"total", timer.Seconds()}};
  result.report = set.Commit(report);
  return result;
}

}  // namespace al
