// OutputSet (al/core/output_set.hpp): journals, the commit, and what the lock records at the end.
#include <fcntl.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/core/interrupts.hpp"
#include "al/core/output_set.hpp"
#include "al/core/report.hpp"
#include "src/core/output_set_internal.hpp"

namespace al {
namespace {

using namespace output_set;

// Sets nested in this one (demo's refine_bk/, ...) name their inputs and outputs by staging paths;
// after the commit those live under --out, so their reports are made to say so.
void RewriteNestedReports(const fs::path& staging, const fs::path& out) {
  const std::string from = nlohmann::json(staging.string()).dump(), to = nlohmann::json(out.string()).dump();
  const std::string from_body = from.substr(1, from.size() - 2), to_body = to.substr(1, to.size() - 2);
  for (fs::recursive_directory_iterator it(staging), end; it != end; ++it) {
    if (it->path().filename() != "report.json" || it->path().parent_path() == staging) continue;
    std::string text = ReadInputFile(it->path().string(), std::uint64_t(1) << 30, Links::kRefuse);
    bool changed = false;
    for (std::size_t at = text.find(from_body); at != std::string::npos; at = text.find(from_body, at + to_body.size())) {
      text.replace(at, from_body.size(), to_body);
      changed = true;
    }
    if (changed) WriteFileAtomically(it->path(), text);
  }
}

// A shell sitting in --out (or below it) would be left in the deleted old folder by an exchange.
bool InsideCwd(const fs::path& out) {
  std::error_code ec;
  const fs::path cwd = fs::weakly_canonical(fs::current_path(ec), ec);
  const fs::path rel = cwd.lexically_relative(out);
  return !ec && !rel.empty() && *rel.begin() != "..";
}

// The mode the published folder gets: the folder it replaces keeps its mode (TryExchange); a new
// one gets what mkdir would have given it (the staging folder was made 0700).
void SetPublishedMode(int dirfd, const std::string& staging, const fs::path& out) {
  struct stat st {};
  const mode_t mode = ::stat(out.c_str(), &st) == 0 ? st.st_mode & 07777 : 0777 & ~CurrentUmask();
  ::fchmodat(dirfd, staging.c_str(), mode, 0);
}

}  // namespace

void OutputTransaction::RecordNow() const {
  lock->Record({::getpid(), staging_name, commit_name, claims});
}

void OutputTransaction::Finish(const fs::path& out, const std::vector<std::string>& settled) {
  if (!lock) return;  // never taken: nothing of this run to record
  if (!commit_name.empty() && output_set::IsOwnFolderAt(dir.get(), commit_name)) {
    staging_name.clear();  // a commit that failed half-way: the record lets the next run finish it
    try {
      RecordNow();
    } catch (const Error&) {
    }
    return;
  }
  std::vector<std::string> kept;
  for (const auto& j : claims)
    if (!Contains(settled, j) && IsOwnFileAt(AT_FDCWD, (out / j).string())) kept.push_back(j);
  if (kept.empty()) {
    lock->Remove();
    return;
  }
  claims = kept;
  staging_name.clear();
  commit_name.clear();
  try {
    RecordNow();
  } catch (const Error&) {
    // A full disk may refuse even this; the record then still names this run's (now removed)
    // staging and the journals it claimed earlier, which is as good for the next run.
  }
}

fs::path OutputSet::Journal(const std::string& name) {
  if (!Contains(options_.journals, name)) options_.journals.push_back(name);
  if (!Contains(txn_->claims, name)) {
    txn_->claims.push_back(name);
    txn_->RecordNow();  // before the file exists: a kill right after creating it leaves it claimed
    if (txn_->interrupt_handle) SetInterruptLock(txn_->interrupt_handle, "");
  }
  EnsureDirectory(out_);
  return out_ / name;
}

int OutputSet::OpenJournal(const std::string& name) {
  const fs::path path = Journal(name);
  const int fd = ::open(path.c_str(), O_RDWR | O_APPEND | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0666);
  if (fd < 0)
    throw FileError(path.string(), errno == ELOOP ? "is a symbolic link; al-refine does not follow links inside "
                                                    "its output folders"
                                                  : std::string("cannot open for appending: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != ::geteuid()) {
    ::close(fd);
    throw FileError(path.string(), "is not a regular file of this user; refusing to append to it");
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

void OutputSet::StageInsteadOfJournal(const std::string& name) {
  std::erase(options_.journals, name);
  std::erase(adopted_journals_, name);
}

nlohmann::json OutputSet::Commit(nlohmann::json report) {
  if (committed_) throw Error(options_.flag + " " + out_.string() + ": output set committed twice", ExitCode::kInternal);
  RewriteNestedReports(staging_, out_);
  for (const auto& w : warnings_) report["warnings"].push_back(w);
  report["manifest"] = BuildManifest(staging_, out_, options_.journals);
  WriteReport(staging_, report);
  Ownership own = ReadOwnership(out_);
  own.journals.insert(adopted_journals_.begin(), adopted_journals_.end());
  own.journals.insert(options_.journals.begin(), options_.journals.end());
  const std::vector<std::string> staged = Entries(staging_);
  const auto foreign = ForeignCollisions(staged, out_, own);
  if (!foreign.empty() && !options_.force) throw Error(ForeignMessage(options_.flag, out_, foreign));
  std::vector<std::string> kept_foreign, old_owned;
  const std::vector<std::string> present = Entries(out_);
  for (const auto& n : present) {
    if (Contains(staged, n) || own.journals.count(n)) continue;
    (Owned(own, out_, n) ? old_owned : kept_foreign).push_back(n);
  }
  {
    const auto hold = HoldInterrupts();  // from here an interrupt waits for the set to be in place
    Publish(kept_foreign, old_owned, present);
    committed_ = true;
    UnregisterInterruptFolder(txn_->interrupt_handle);
    txn_->interrupt_handle = 0;
  }
  txn_->Finish(out_, options_.journals);
  txn_.reset();
  return report;
}

// Moves the staged set into place: a rename when --out is new, else an exchange, else (foreign
// files to keep, staged inside --out, a shell in --out, no exchange on this filesystem) the
// journaled commit.
void OutputSet::Publish(const std::vector<std::string>& kept_foreign, const std::vector<std::string>& old_owned,
                        const std::vector<std::string>& present) {
  const int dir = txn_->dir.get();
  const std::string& staging = txn_->staging_name;
  SetPublishedMode(dir, staging, out_);
  if (!inside_ && ::renameat2(dir, staging.c_str(), dir, name_.c_str(), RENAME_NOREPLACE) == 0) return;
  if (!inside_ && kept_foreign.empty() && !InsideCwd(out_) &&
      TryExchange(dir, staging, out_, options_.journals, present))
    return;
  std::string removals;
  for (const auto& n : old_owned) removals += n + "\n";
  WriteFileAtomically(staging_ / kRemoveList, removals);
  if (::renameat2(dir, staging.c_str(), dir, txn_->commit_name.c_str(), RENAME_NOREPLACE) != 0)
    throw FileError(out_.string(), std::string("cannot commit the output set: ") + std::strerror(errno));
  RollForward(dir, txn_->dir_path, txn_->commit_name, out_);
}

}  // namespace al
