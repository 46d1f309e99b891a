// Pieces of the output-set transaction (al/core/output_set.hpp) shared by its source files.
#pragma once
#include <sys/types.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "src/core/folder_fd.hpp"
#include "src/core/output_lock.hpp"

namespace al::output_set {

namespace fs = std::filesystem;

// Control files inside a staging or commit folder; never part of a set.
inline constexpr const char* kRemoveList = ".al-remove";  // old entries the commit removes
inline bool IsControlFile(const std::string& name) { return name.rfind(".al-", 0) == 0; }

// What a previous run's report.json says is al-refine's own in an output folder. A report counts
// only when it is a regular file of this user (a neighbour's forged manifest owns nothing).
struct Ownership {
  bool report_is_ours = false;       // report.json is an al-refine report of this user
  std::set<std::string> files;       // manifest paths ("images/a.png")
  std::set<std::string> journals;    // append-only entries (top-level names)
};
Ownership ReadOwnership(const fs::path& out);
// out/top may be replaced: report.json of ours, a listed regular file or journal of this user, or
// a folder whose every file is such a file (an empty folder holds nothing to lose). Links never.
bool Owned(const Ownership& own, const fs::path& out, const std::string& top);

bool Contains(const std::vector<std::string>& v, const std::string& s);
// The names (of `names`) under which out holds something that is not al-refine's, each with what
// it is when that says why (" (a FIFO)", " (another user's)").
std::vector<std::string> ForeignCollisions(const std::vector<std::string>& names, const fs::path& out,
                                           const Ownership& own);
std::string ForeignMessage(const std::string& flag, const fs::path& out, const std::vector<std::string>& names);

// Top-level entry names of a folder, sorted, control files excluded.
std::vector<std::string> Entries(const fs::path& dir);
std::vector<std::string> EntriesAt(int dirfd);

// The manifest of a staged set: every regular file under `staging` (relative path, bytes, SHA-256
// up to 64 MiB) and the journals in `out` (committed prefix: bytes and its hash, append_only).
nlohmann::json BuildManifest(const fs::path& staging, const fs::path& out, const std::vector<std::string>& journals);

// Where a set's lock and transaction folders live: beside --out (".NAME." prefix) or, for a set
// staged inside --out, in it ("." prefix).
struct TransactionNames {
  std::string prefix;  // ".NAME." or "."
  std::string Lock() const { return prefix + "al-lock"; }
  std::string Staging(const std::string& claim) const { return prefix + "al-staging-" + claim; }
  std::string Commit(const std::string& claim) const { return prefix + "al-commit-" + claim; }
};
// Entries of `dir` that look like transaction folders of `names` (".NAME.al-staging-...",
// ".NAME.al-commit-...", the older ".NAME.eval-tmp-..."), sorted: only those a lock record names
// are acted on; the rest are a neighbour's or an older al-refine's, and are left alone.
std::vector<std::string> LookAlikes(const fs::path& dir, const TransactionNames& names);

// Finishes a per-entry commit from the folder commit_name in dirfd (the folder `dir`) into `out`
// (idempotent, so a killed commit is finished by the next run).
void RollForward(int dirfd, const fs::path& dir, const std::string& commit_name, const fs::path& out);
// Swaps dirfd/staging and dirfd/out_name atomically; false when the filesystem cannot (the caller
// falls back). `replaced`: the entries of out the commit decided to replace (the rest, if any
// appeared meanwhile, is moved back). Journals enter the new set as hard links.
bool TryExchange(int dirfd, const std::string& staging, const fs::path& out, const std::vector<std::string>& journals,
                 const std::vector<std::string>& replaced);

}  // namespace al::output_set

namespace al {

// The lock of an output set and what it records: the folder holding the lock and the transaction
// folders (beside --out, or --out itself), this run's transaction folder names, and the journals
// claimed (this run's, and earlier runs' under other names, carried on).
struct OutputTransaction {
  output_set::UniqueFd dir;
  std::filesystem::path dir_path;
  output_set::TransactionNames names;
  std::unique_ptr<output_set::OutputLock> lock;
  std::string staging_name, commit_name;
  std::vector<std::string> claims;
  std::size_t interrupt_handle = 0;  // 0: staging not registered for removal on interrupt

  void RecordNow() const;
  // The journals still claimed once the run ends (those that exist as this user's files in out,
  // minus `settled`: the ones a committed manifest now lists); the lock file is removed when none.
  void Finish(const std::filesystem::path& out, const std::vector<std::string>& settled);
};

}  // namespace al
