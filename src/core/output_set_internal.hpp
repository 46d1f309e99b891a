// Pieces of the output-set transaction (al/core/output_set.hpp) shared by its source files.
#pragma once
#include <sys/types.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace al::output_set {

namespace fs = std::filesystem;

// Control files inside a staging or commit folder; never part of a set.
inline constexpr const char* kJournalClaims = ".al-journals";  // journals this run appends to
inline constexpr const char* kRemoveList = ".al-remove";       // old entries the commit removes
inline bool IsControlFile(const std::string& name) { return name.rfind(".al-", 0) == 0; }

// What a previous run's report.json says is al-refine's own in an output folder.
struct Ownership {
  bool report_is_ours = false;       // report.json is an al-refine report
  std::set<std::string> files;       // manifest paths ("images/a.png")
  std::set<std::string> journals;    // append-only entries (top-level names)
};
Ownership ReadOwnership(const fs::path& out);
// out/top may be replaced: report.json of ours, a listed file or journal, or a folder whose every
// file is listed (an empty folder holds nothing to lose).
bool Owned(const Ownership& own, const fs::path& out, const std::string& top);

// Top-level entry names of a folder, sorted, control files excluded.
std::vector<std::string> Entries(const fs::path& dir);

// The manifest of a staged set: every regular file under `staging` (relative path, bytes, SHA-256
// up to 64 MiB) and the journals in `out` (committed prefix: bytes and its hash, append_only).
nlohmann::json BuildManifest(const fs::path& staging, const fs::path& out, const std::vector<std::string>& journals);

// Stale transaction folders of `name` in `parent`: ".NAME.al-staging-PID", ".NAME.al-commit-PID"
// and the older ".NAME.eval-tmp-PID"; and, inside NAME, ".al-staging-PID" and ".al-commit-PID"
// (the folders of a set staged inside --out, see OutputSet).
struct Stale {
  fs::path path;
  pid_t pid = 0;
  bool commit = false;  // a committed journal folder: roll forward, never delete
};
std::vector<Stale> FindTransactions(const fs::path& parent, const std::string& name);
bool ProcessAlive(pid_t pid);

// Finishes a per-entry commit (idempotent, so a killed commit is finished by the next run).
void RollForward(const fs::path& commit_dir, const fs::path& out);
// Swaps staging and out atomically; false when the filesystem cannot (caller falls back).
// `replaced`: the entries of out the commit decided to replace (the rest, if any appeared
// meanwhile, is moved back).
bool TryExchange(const fs::path& staging, const fs::path& out, const std::vector<std::string>& journals,
                 const std::vector<std::string>& replaced);

// Exclusive advisory lock on a folder for the lifetime of the object (commits and recovery).
class DirLock {
 public:
  explicit DirLock(const fs::path& dir);
  ~DirLock();
  DirLock(const DirLock&) = delete;
  DirLock& operator=(const DirLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace al::output_set
