// An output folder (--out) written as one transaction (docs/reliability.md):
//  - Before computing, OutputSet takes the folder's lock (".NAME.al-lock" beside --out, flock:
//    one writer at a time; a second waits with a message, or refuses with --no-wait), checks that
//    --out can be written, refuses inputs that lie inside --out where this run would replace them,
//    refuses foreign files (not listed by a previous al-refine manifest of this user) under the
//    names it will write unless --force, and finishes what the lock's record says an earlier,
//    killed or failed run left (its staging, an interrupted commit, the journals it claimed).
//    Folders that merely look like al-refine's bookkeeping are left alone, with a warning.
//  - Everything is written into a sibling staging folder ".NAME.al-staging-PID-TOKEN", made with
//    mkdir (0700; TOKEN random, recorded in the lock). Inside --out (".al-staging-PID-TOKEN",
//    lock ".al-lock") when --out is a mount point or its parent is read-only; such a set is
//    committed entry by entry, as below.
//  - Commit writes report.json last, with a manifest of the set's files (path, bytes, SHA-256),
//    and makes the new set visible at once: the staging folder is exchanged with --out
//    (renameat2 RENAME_EXCHANGE), so a reader sees the previous complete set or the new one.
//    When --out also holds files al-refine did not write (those are kept), entries move one by
//    one from a committed journal folder ".NAME.al-commit-PID-TOKEN": report.json is removed
//    first and written last, and a killed commit is finished by the next run.
//  - Append-only journals (sweep's results.jsonl) live in --out itself and survive kills and
//    failures (the lock records the claim); the manifest records the committed prefix.
//  - Everything under --out is opened without following links and without blocking.
#pragma once
#include <filesystem>
#include <functional>
#include <memory>
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
  bool wait = true;                              // another writer holds --out: wait (else refuse)
  std::string flag = "--out";                    // how messages name the folder
};

struct OutputTransaction;  // the lock, its record and the transaction folders (output_set.cpp)

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
  // An append-only file that lives in --out itself and is claimed by this run (in the lock's
  // record), so that the journal of a killed or failed run is recognised as al-refine's own by the
  // next one. Journal returns its path (the caller creates it); OpenJournal opens it for reading
  // and appending (created if missing), never through a link and never blocking, and returns the
  // descriptor (the caller closes it).
  std::filesystem::path Journal(const std::string& name);
  int OpenJournal(const std::string& name);
  // A name declared as a journal that this run writes whole instead (staged like any other file,
  // replacing the committed one at commit): sweep's shard.json when its grid grew.
  void StageInsteadOfJournal(const std::string& name);
  // What the set found and left alone (folders that look like al-refine's bookkeeping but that
  // no al-refine run recorded); Commit adds them to the report's warnings.
  const std::vector<std::string>& warnings() const { return warnings_; }
  // Adds report["manifest"], writes report.json last and publishes the set. Returns the report
  // as written.
  nlohmann::json Commit(nlohmann::json report);

 private:
  std::filesystem::path out_, parent_, staging_;
  std::string name_;
  OutputSetOptions options_;
  std::vector<std::string> adopted_journals_;  // claimed by killed or failed runs of the same --out
  std::vector<std::string> warnings_;
  bool inside_ = false;     // staged inside --out (a mount point, or a read-only parent)
  bool committed_ = false;
  std::vector<std::filesystem::path> created_parents_;  // missing parents of --out it created
  std::unique_ptr<OutputTransaction> txn_;
  void Open(const std::filesystem::path& out);
  void RecoverPrevious();
  void NoteLookAlikes();
  void CreateStaging();
  void Publish(const std::vector<std::string>& kept_foreign, const std::vector<std::string>& old_owned,
               const std::vector<std::string>& present);
  void Abandon();  // a run that never committed: its staging goes, its claims stay recorded
};

// The "force" default every OutputSet of this process starts from (the CLI's --force).
void SetForceOutputs(bool force);
bool ForceOutputs();
// Whether output sets of this process wait for another writer of the same --out (the CLI's
// --no-wait sets false: refuse with exit 2 instead).
void SetWaitForOutputs(bool wait);
// Where output sets tell a person what they are doing that takes time (waiting for the lock);
// the CLI prints to stderr. Library default: nowhere.
void SetOutputNotices(std::function<void(const std::string&)> notice);

// What `al-refine info --verify DIR` reports: is DIR a complete al-refine output set?
struct OutputSetStatus {
  std::string state;                  // "complete", "extended" (a journal grew), "incomplete", "not_a_set"
  std::string command;                // from report.json
  std::size_t files = 0;              // listed by the manifest
  std::vector<std::string> problems;  // missing / resized / changed files, interrupted runs
  std::vector<std::string> notes;     // a writer at work now; look-alike folders left alone
  nlohmann::json ToJson() const;
};
OutputSetStatus VerifyOutputSet(const std::filesystem::path& dir);
// The check itself on a report's text (fuzzing): manifest paths must stay inside dir and name
// regular files, so a hostile manifest cannot make it read /dev/zero or ../../etc.
OutputSetStatus VerifyManifest(const std::string& report_text, const std::filesystem::path& dir);

}  // namespace al
