// An output folder (--out) written as one transaction (docs/reliability.md):
//  - Before computing, OutputSet checks that --out can be written, refuses inputs that lie inside
//    --out where this run would replace them, refuses foreign files (not listed by a previous
//    al-refine manifest) under the names it will write unless --force, and cleans the staging of
//    killed runs for the same --out (only entries of its own pattern whose process is gone).
//  - Everything is written into a sibling staging folder ".NAME.al-staging-PID" (inside --out,
//    ".al-staging-PID", when --out is a mount point or its parent is read-only; such a set is
//    committed entry by entry, as below).
//  - Commit writes report.json last, with a manifest of the set's files (path, bytes, SHA-256),
//    and makes the new set visible at once: the staging folder is exchanged with --out
//    (renameat2 RENAME_EXCHANGE), so a reader sees the previous complete set or the new one.
//    When --out also holds files al-refine did not write (those are kept), entries move one by
//    one from a committed journal folder ".NAME.al-commit-PID": report.json is removed first and
//    written last, and a killed commit is finished by the next run.
//  - Append-only journals (sweep's results.jsonl) live in --out itself and survive kills; the
//    manifest records the committed prefix (bytes and its hash).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace al {

struct OutputSetOptions {
  OutputSetOptions() = default;
  explicit OutputSetOptions(std::string command_, std::vector<std::filesystem::path> inputs_ = {},
                            std::vector<std::string> planned_ = {})
      : command(std::move(command_)), inputs(std::move(inputs_)), planned(std::move(planned_)) {}
  std::string command;                           // which command writes the set (messages)
  std::vector<std::filesystem::path> inputs;     // files or folders this run reads
  std::vector<std::string> planned;              // top-level names this run will write, if known
  std::vector<std::string> journals;             // append-only files kept in --out (see Journal)
  bool force = false;                            // replace foreign entries with colliding names
  std::string flag = "--out";                    // how messages name the folder
};

class OutputSet {
 public:
  // All the checks above; throws al::Error (exit 2) before anything is computed.
  OutputSet(const std::filesystem::path& out, OutputSetOptions options);
  ~OutputSet();  // unless committed: drops the staging folder and the parent folders it created
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  // The staging folder: write every output here.
  const std::filesystem::path& dir() const { return staging_; }
  const std::filesystem::path& out() const { return out_; }
  // An append-only file that lives in --out itself (created if missing) and is claimed by this
  // run, so that a killed run's journal is recognised as al-refine's own by the next one.
  std::filesystem::path Journal(const std::string& name);
  // Adds report["manifest"], writes report.json last and publishes the set. Returns the report
  // as written.
  nlohmann::json Commit(nlohmann::json report);

 private:
  std::filesystem::path out_, parent_, staging_;
  std::string name_;
  OutputSetOptions options_;
  std::vector<std::string> adopted_journals_;  // claimed by killed runs of the same --out
  bool inside_ = false;     // staged inside --out (a mount point, or a read-only parent)
  bool committed_ = false;
  std::vector<std::filesystem::path> created_parents_;  // missing parents of --out it created
  void Open(const std::filesystem::path& out);
  // ".NAME.KIND-PID" beside --out, or ".KIND-PID" inside it.
  std::filesystem::path TransactionPath(const std::string& kind) const;
};

// The "force" default every OutputSet of this process starts from (the CLI's --force).
void SetForceOutputs(bool force);
bool ForceOutputs();

// What `al-refine info --verify DIR` reports: is DIR a complete al-refine output set?
struct OutputSetStatus {
  std::string state;                  // "complete", "extended" (a journal grew), "incomplete", "not_a_set"
  std::string command;                // from report.json
  std::size_t files = 0;              // listed by the manifest
  std::vector<std::string> problems;  // missing / resized / changed files, interrupted runs
  nlohmann::json ToJson() const;
};
OutputSetStatus VerifyOutputSet(const std::filesystem::path& dir);
// The check itself on a report's text (fuzzing): manifest paths must stay inside dir and name
// regular files, so a hostile manifest cannot make it read /dev/zero or ../../etc.
OutputSetStatus VerifyManifest(const std::string& report_text, const std::filesystem::path& dir);

}  // namespace al
