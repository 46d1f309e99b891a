// MergeSweeps (al/refine/sweep.hpp): shard outputs -> one sweep output. The folders must be
// slices of one sweep (shard.json); missing shards and points are counted and an incomplete set is
// refused unless allowed; records are deduplicated by id, in canonical order, with CSV, charts and
// report.
#include <filesystem>
#include <map>
#include <optional>
#include <unordered_map>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/output_set.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/refine/sweep.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

struct LoadedShard {
  MergedShard status;
  ShardInfo info;
  std::vector<nlohmann::json> records;
};

std::string JoinIndices(const std::vector<std::size_t>& v, const char* separator) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? separator : "") + std::to_string(v[i]);
  return out;
}

// shard.json and results.jsonl of every folder (a folder given twice is read twice: its records
// count as duplicates, as before shard.json existed).
std::vector<LoadedShard> LoadShards(const MergeOptions& o, nlohmann::json& report, std::vector<std::string>& warnings) {
  std::vector<LoadedShard> shards;
  std::error_code ec;
  for (const auto& d : o.shard_dirs) {
    if (!fs::is_directory(d)) throw Error(d + ": no such folder", ExitCode::kBadInput);
    if (!o.out_dir.empty() && fs::equivalent(fs::path(d), fs::path(o.out_dir), ec))
      throw Error(d + ": --out must differ from the shard directories", ExitCode::kUsage);
    LoadedShard s;
    s.info = ReadShardInfo(d);
    const std::string path = (fs::path(d) / "results.jsonl").string();
    if (!fs::is_regular_file(path)) throw Error(d + ": no results.jsonl (not a sweep output directory)", ExitCode::kBadInput);
    AddInputFile(report, "shard " + d, path);
    JsonlContents c = ReadResultsJsonl(path);
    if (c.truncated_tail)
      warnings.push_back(path + ": ends in a truncated line (a killed shard); rerun that shard to complete it");
    s.status = {d, s.info.shard, s.info.points_in_shard(), 0, c.records.size(), c.truncated_tail};
    s.records = std::move(c.records);
    shards.push_back(std::move(s));
  }
  return shards;
}

// Every folder must be a slice of the first folder's sweep.
void CheckOneSweep(const std::vector<LoadedShard>& shards) {
  const LoadedShard& ref = shards.front();
  for (const auto& s : shards) {
    const std::vector<std::string> diff = SweepDifferences(ref.info, s.info);
    if (diff.empty()) continue;
    std::string what;
    for (const auto& d : diff) what += (what.empty() ? "" : "; ") + d;
    throw Error(s.status.dir + " (shard " + s.info.shard.ToString() + ") is not a shard of the same sweep as " +
                    ref.status.dir + " (shard " + ref.info.shard.ToString() + "); " + ref.status.dir + " vs " +
                    s.status.dir + ": " + what,
                ExitCode::kBadInput);
  }
}

// Deduplicates by id into `records`: first occurrence wins, a differing duplicate is a conflict;
// ids that are not points of the sweep are left out. Marks found[j] for each job j found.
std::vector<nlohmann::json> Combine(std::vector<LoadedShard>& shards, const std::vector<std::string>& sweep_ids,
                                    std::vector<bool>& found, MergeResult& result) {
  std::unordered_map<std::string, std::size_t> job_of;
  for (std::size_t j = 0; j < sweep_ids.size(); ++j) job_of[sweep_ids[j]] = j;
  std::map<std::string, std::size_t> index;  // id -> position in records
  std::vector<nlohmann::json> records;
  std::string foreign_example;
  for (auto& s : shards) {
    for (auto& r : s.records) {
      const std::string id = r["id"].get<std::string>();
      const auto job = job_of.find(id);
      if (job == job_of.end()) {
        ++result.foreign_records;
        if (foreign_example.empty()) foreign_example = id + " in " + s.status.dir;
        continue;
      }
      s.status.points_found += job->second >= s.info.first && job->second < s.info.end;
      const auto it = index.find(id);
      if (it == index.end()) {
        index[id] = records.size();
        found[job->second] = true;
        records.push_back(std::move(r));
        continue;
      }
      ++result.duplicates;
      if (RecordWithoutTimings(records[it->second]) != RecordWithoutTimings(r)) {
        ++result.conflicts;
        result.warnings.push_back(id + ": results differ between shards (kept the first, from an earlier directory)");
      }
    }
    s.records.clear();
  }
  if (result.foreign_records)
    result.warnings.push_back(std::to_string(result.foreign_records) +
                              " records are not points of this sweep (e.g. " + foreign_example +
                              ", from an earlier grid in that folder): left out");
  return records;
}

// Which shard indices were given no folder and which have a point not found; the verdict.
void Completeness(const std::vector<LoadedShard>& shards, const std::vector<bool>& found, MergeResult& result) {
  const std::size_t n = result.shard_count;
  std::vector<bool> given(n, false);
  for (const auto& s : shards) given[s.info.shard.index] = true;
  for (std::size_t i = 0; i < n; ++i) {
    const auto [first, end] = ShardRange(result.points_total, {i, n});
    bool all = true;
    for (std::size_t j = first; j < end && all; ++j) all = found[j];
    if (!given[i]) result.missing_shards.push_back(i);
    if (!all || !given[i]) result.incomplete_shards.push_back(i);
  }
  for (bool f : found) result.points_found += f;
  result.complete = result.incomplete_shards.empty();
  if (result.complete) return;
  std::vector<std::size_t> partial;
  for (std::size_t i : result.incomplete_shards)
    if (given[i]) partial.push_back(i);
  result.message = "incomplete set: " + std::to_string(result.points_found) + " of " +
                   std::to_string(result.points_total) + " points found";
  if (!result.missing_shards.empty())
    result.message += "; no folder for shard " + JoinIndices(result.missing_shards, ", ") + " (of " + std::to_string(n) + ")";
  if (!partial.empty()) result.message += "; shard " + JoinIndices(partial, ", ") + " only partly done";
  result.message += "; rerun those shards (the same sweep command with their --shard i/n; on SLURM, the "
                    "resubmit script beside submit, given the sweep's folder), or merge with --allow-partial";
}

nlohmann::json ResultJson(const MergeOptions& o, const MergeResult& r, const ShardInfo& sweep) {
  nlohmann::json shards = nlohmann::json::array();
  for (const auto& s : r.shards) shards.push_back(s.ToJson());
  return {{"params", {{"shards", o.shard_dirs}, {"out", o.out_dir}, {"allow_partial", o.allow_partial}}},
          {"sweep",
           {{"shard_count", r.shard_count}, {"points_total", r.points_total}, {"grid", sweep.grid},
            {"scenes", sweep.scenes}, {"fixed", sweep.fixed}, {"binary", sweep.binary}}},
          {"complete", r.complete},
          {"shards", shards},
          {"missing_shards", r.missing_shards},
          {"incomplete_shards", r.incomplete_shards},
          {"counts",
           {{"records", r.records}, {"points_total", r.points_total}, {"points_found", r.points_found},
            {"points_missing", r.points_total - r.points_found}, {"duplicates", r.duplicates},
            {"conflicts", r.conflicts}, {"foreign_records", r.foreign_records}}}};
}

// The merged folder is one output set (al/core/output_set.hpp); checked before any shard is read.
OutputSetOptions MergeOutputSetOptions(const MergeOptions& o) {
  OutputSetOptions so("merge");
  so.inputs.assign(o.shard_dirs.begin(), o.shard_dirs.end());
  so.planned = {"results.jsonl", "results.csv", "report.json"};
  return so;
}

void WriteMerged(OutputSet& set, std::vector<nlohmann::json>& records, const MergeOptions& o, const ShardInfo& sweep,
                 nlohmann::json& report, MergeResult& result, const Timer& timer) {
  SortRecords(records);
  WriteFileAtomically(set.dir() / "results.jsonl", [&](std::ostream& os) {
    for (const auto& r : records) os << r.dump() << '\n';
  });
  const nlohmann::json summaries = WriteSweepSummaries(set.dir().string(), records);
  for (const auto& s : summaries["skipped_charts"])
    result.warnings.push_back("chart " + s["name"].get<std::string>() + " skipped: " + s["reason"].get<std::string>());
  report.update(ResultJson(o, result, sweep));
  report["outputs"] = summaries;
  for (const auto& w : result.warnings) report["warnings"].push_back(w);
  report["timings_s"] = {{"total", timer.Seconds()}};
  result.report = set.Commit(report);
  result.written = true;
}

}  // namespace

void MergeOptions::Check() const {
  if (shard_dirs.empty()) throw Error("merge: no shard directory given", ExitCode::kUsage);
  if (out_dir.empty() && !check_only) throw Error("--out is required (or --check)", ExitCode::kUsage);
}

nlohmann::json MergedShard::ToJson() const {
  return {{"dir", dir}, {"shard", shard.ToString()}, {"points_in_shard", points_in_shard},
          {"points_found", points_found}, {"records", records}, {"truncated_tail", truncated_tail},
          {"complete", points_found == points_in_shard}};
}

std::string MergeResult::BriefReport() const {
  std::string out = "merge: " + std::to_string(shard_count - missing_shards.size()) + " of " +
                    std::to_string(shard_count) + " shards, " + std::to_string(points_found) + " of " +
                    std::to_string(points_total) + " points (" + std::to_string(shards.size()) + " folders, " +
                    std::to_string(records) + " records, " + std::to_string(duplicates) + " duplicates, " +
                    std::to_string(conflicts) + " conflicts)" + (complete ? ": complete" : ": INCOMPLETE") + "\n";
  for (const auto& s : shards)
    if (s.points_found < s.points_in_shard)
      out += "  shard " + s.shard.ToString() + "  " + s.dir + ": " + std::to_string(s.points_found) + " of " +
             std::to_string(s.points_in_shard) + " points" + (s.truncated_tail ? " (ends in a truncated line: killed)" : "") + "\n";
  for (std::size_t i : missing_shards)
    out += "  shard " + std::to_string(i) + "/" + std::to_string(shard_count) + ": no folder given\n";
  if (!incomplete_shards.empty()) out += "incomplete shards: " + JoinIndices(incomplete_shards, " ") + "\n";
  return out;
}

MergeResult MergeSweeps(const MergeOptions& o) {
  Timer timer;
  o.Check();
  std::optional<OutputSet> set;
  if (!o.check_only) set.emplace(o.out_dir, MergeOutputSetOptions(o));
  MergeResult result;
  nlohmann::json report = NewReport("merge");
  std::vector<LoadedShard> shards = LoadShards(o, report, result.warnings);
  CheckOneSweep(shards);
  const ShardInfo sweep = shards.front().info;
  result.shard_count = sweep.shard.count;
  result.points_total = sweep.points_total;
  std::vector<bool> found(result.points_total, false);
  std::vector<nlohmann::json> records = Combine(shards, SweepPointIds(sweep, 0, sweep.points_total), found, result);
  result.records = records.size();
  for (const auto& s : shards) result.shards.push_back(s.status);
  Completeness(shards, found, result);
  if (!result.complete && !o.allow_partial) result.exit_code = static_cast<int>(ExitCode::kBadInput);
  if (o.check_only || result.exit_code != 0) return result;
  WriteMerged(*set, records, o, sweep, report, result, timer);
  return result;
}

}  // namespace al
