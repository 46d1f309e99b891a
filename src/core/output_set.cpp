// OutputSet (al/core/output_set.hpp): the lock and the checks before computing (the commit is in
// output_commit.cpp).
#include "al/core/output_set.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/interrupts.hpp"
#include "al/core/report.hpp"
#include "src/core/output_set_internal.hpp"

namespace al {
namespace {

using namespace output_set;

bool g_force_outputs = false;
bool g_wait_for_outputs = true;
std::function<void(const std::string&)>& NoticeSink() {
  static std::function<void(const std::string&)> sink;
  return sink;
}

std::set<fs::path>& ActiveSets() {  // one staging folder per --out and process
  static std::set<fs::path> active;
  return active;
}

// Canonical absolute form (symlinks resolved where the path exists).
fs::path Canonical(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(fs::absolute(p), ec);
  if (ec) c = fs::absolute(p).lexically_normal();
  if (!c.has_filename() && c.has_parent_path() && c != c.root_path()) c = c.parent_path();
  return c;
}

bool Writable(const fs::path& dir) { return ::access(dir.c_str(), W_OK | X_OK) == 0; }

bool OnOtherDevice(const fs::path& a, const fs::path& b) {
  struct stat sa {}, sb {};
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev != sb.st_dev;
}

// The missing folders from `dir` up to its first existing ancestor, deepest first.
std::vector<fs::path> MissingFolders(const fs::path& dir) {
  std::vector<fs::path> missing;
  std::error_code ec;
  for (fs::path p = dir; !p.empty() && p != p.root_path() && !fs::exists(p, ec); p = p.parent_path())
    missing.push_back(p);
  return missing;
}

// Removes the folders a run created, deepest first, as long as they are empty (fs::remove never
// deletes a folder with something in it: whatever another process put there stays).
void RemoveEmptyFolders(const std::vector<fs::path>& folders) {
  std::error_code ec;
  for (const fs::path& p : folders) fs::remove(p, ec);
}

// Checks that --out can be written; true when the set must be staged inside --out: --out is a
// mount point (a container's bind mount, a mounted disk: a sibling staging folder would be on
// another filesystem, where nothing can be renamed into --out) or its parent is read-only.
// `created`: the parent folders it had to create (a run that never commits removes them).
bool CheckWritable(const fs::path& out, const fs::path& parent, const std::string& flag_name,
                   std::vector<fs::path>& created) {
  const std::string flag = flag_name + " " + out.string();
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec)) throw Error(flag + ": exists and is not a folder");
  if (fs::is_directory(out, ec)) {
    if (!Writable(out)) throw Error(flag + ": cannot write: " + std::strerror(errno));
    return OnOtherDevice(out, parent) || !Writable(parent);
  }
  created = MissingFolders(parent);
  fs::create_directories(parent, ec);
  if (ec || !fs::is_directory(parent)) {
    RemoveEmptyFolders(created);
    throw Error(flag + ": cannot create " + parent.string() + ": " + ec.message());
  }
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    throw Error(flag + ": cannot write in " + parent.string() + ": " + std::strerror(errno));
  return false;
}

// An input inside --out whose top-level entry this run replaces would be lost: refuse it.
void CheckInputs(const OutputSetOptions& o, const fs::path& out, const Ownership& own) {
  for (const auto& input : o.inputs) {
    if (input.empty()) continue;
    const fs::path in = Canonical(input);
    const fs::path rel = in.lexically_relative(out);
    if (rel.empty() || *rel.begin() == "..") continue;
    const std::string top = rel.begin()->string();
    const bool whole = top == ".";
    if (!whole && !Owned(own, out, top) && !Contains(o.planned, top) && !Contains(o.journals, top)) continue;
    if (whole && Entries(out).empty()) continue;
    const bool written = !whole && (Contains(o.planned, top) || Contains(o.journals, top));
    const std::string why = whole     ? "this " + o.command + " run replaces what is there"
                            : written ? "this " + o.command + " run writes " + top
                                      : "it belongs to the earlier al-refine output set there, which this " + o.command + " run replaces";
    throw Error(o.flag + " " + out.string() + ": the input " + input.string() + " lies inside it and " + why +
                "; choose another " + o.flag + " or move the input");
  }
}

}  // namespace

namespace output_set {

bool Contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

std::string ForeignMessage(const std::string& flag, const fs::path& out, const std::vector<std::string>& names) {
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  return flag + " " + out.string() + " holds " + list +
         ", which no al-refine manifest there lists; refusing to replace what al-refine did not write "
         "(choose another " + flag + ", move it away, or pass --force)";
}

// " (a FIFO)" for what is not a file or a folder: why the name is not al-refine's is then plain.
std::string KindOf(const struct stat& st) {
  if (S_ISLNK(st.st_mode)) return " (a symbolic link)";
  if (S_ISFIFO(st.st_mode)) return " (a FIFO)";
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) return " (a device)";
  if (S_ISSOCK(st.st_mode)) return " (a socket)";
  if (st.st_uid != ::geteuid()) return " (another user's)";
  return "";
}

std::vector<std::string> ForeignCollisions(const std::vector<std::string>& names, const fs::path& out,
                                           const Ownership& own) {
  std::vector<std::string> foreign;
  for (const auto& n : names)
    if (const auto st = StatAt(AT_FDCWD, (out / n).string()); st && !Owned(own, out, n))
      foreign.push_back(n + KindOf(*st));
  return foreign;
}

}  // namespace output_set

void SetForceOutputs(bool force) { g_force_outputs = force; }
bool ForceOutputs() { return g_force_outputs; }
void SetWaitForOutputs(bool wait) { g_wait_for_outputs = wait; }
void SetOutputNotices(std::function<void(const std::string&)> notice) { NoticeSink() = std::move(notice); }

OutputSet::OutputSet(const fs::path& out, OutputSetOptions options) : options_(std::move(options)) {
  options_.force = options_.force || g_force_outputs;
  options_.wait = options_.wait && g_wait_for_outputs;
  if (out.empty()) throw Error(options_.flag + " is required", ExitCode::kUsage);
  out_ = Canonical(out);
  parent_ = out_.parent_path();
  name_ = out_.filename().string();
  if (name_.empty() || name_ == "." || name_ == ".." || out_ == out_.root_path())
    throw Error(options_.flag + " " + out.string() + ": cannot be a filesystem root");
  if (ActiveSets().count(out_))
    throw Error(options_.flag + " " + out.string() + ": already an output folder of this run");
  inside_ = CheckWritable(out_, parent_, options_.flag, created_parents_);
  try {
    Open(out);
  } catch (...) {
    Abandon();
    throw;
  }
  ActiveSets().insert(out_);
}

// The lock (waiting for another writer), what an earlier run left, the checks, the staging folder.
void OutputSet::Open(const fs::path& out) {
  txn_ = std::make_unique<OutputTransaction>();
  txn_->dir_path = inside_ ? out_ : parent_;
  txn_->names.prefix = inside_ ? "." : "." + name_ + ".";
  txn_->dir = OpenFolder(txn_->dir_path);
  if (!txn_->dir)
    throw FileError(txn_->dir_path.string(), std::string("cannot open the folder of ") + options_.flag + ": " +
                                                 std::strerror(errno));
  txn_->lock = std::make_unique<OutputLock>(txn_->dir.get(), txn_->names.Lock(), txn_->dir_path / txn_->names.Lock(),
                                            out_, options_.wait, NoticeSink());
  RecoverPrevious();
  NoteLookAlikes();
  Ownership own = ReadOwnership(out_);
  own.journals.insert(adopted_journals_.begin(), adopted_journals_.end());
  CheckInputs(options_, out_, own);
  std::vector<std::string> names = options_.planned;
  names.insert(names.end(), options_.journals.begin(), options_.journals.end());
  const auto foreign = ForeignCollisions(names, out_, own);
  if (!foreign.empty() && !options_.force) throw Error(ForeignMessage(options_.flag, out_, foreign));
  CreateStaging();
}

// What the lock's record says the previous holder (killed, or failed) left: its commit is
// finished, its staging removed, its journals adopted (this run's names) or carried on (others).
// Only recorded names are touched, and only when they are this user's real folders.
void OutputSet::RecoverPrevious() {
  const auto& previous = txn_->lock->previous();
  if (!previous) return;
  const int dir = txn_->dir.get();
  if (!previous->commit.empty() && IsOwnFolderAt(dir, previous->commit))
    RollForward(dir, txn_->dir_path, previous->commit, out_);
  if (!previous->staging.empty() && IsOwnFolderAt(dir, previous->staging)) RemoveTreeAt(dir, previous->staging);
  for (const auto& journal : previous->journals) {
    if (!IsOwnFileAt(AT_FDCWD, (out_ / journal).string()) || Contains(txn_->claims, journal)) continue;
    txn_->claims.push_back(journal);
    if (Contains(options_.journals, journal)) adopted_journals_.push_back(journal);
  }
}

void OutputSet::NoteLookAlikes() {
  for (const auto& name : LookAlikes(txn_->dir_path, txn_->names)) {
    warnings_.push_back("left alone: " + (txn_->dir_path / name).string() +
                        " looks like al-refine's bookkeeping for " + out_.string() +
                        ", but no al-refine run recorded it (a neighbour's, or an older al-refine's); "
                        "remove it yourself if it is yours");
    if (NoticeSink()) NoticeSink()(warnings_.back());
  }
}

// ".NAME.al-staging-PID-TOKEN", recorded in the lock before it exists and made with mkdir (a name
// that exists already, planted or not, is never used: another token is drawn).
void OutputSet::CreateStaging() {
  const int dir = txn_->dir.get();
  for (int attempt = 0;; ++attempt) {
    const std::string claim = std::to_string(::getpid()) + "-" + RandomToken();
    txn_->staging_name = txn_->names.Staging(claim);
    txn_->commit_name = txn_->names.Commit(claim);
    txn_->RecordNow();
    if (::mkdirat(dir, txn_->staging_name.c_str(), 0700) == 0) break;
    if (errno != EEXIST || attempt == 8)
      throw FileError((txn_->dir_path / txn_->staging_name).string(),
                      std::string("cannot create the staging folder: ") + std::strerror(errno));
  }
  staging_ = txn_->dir_path / txn_->staging_name;
  txn_->interrupt_handle =
      RegisterInterruptFolder(dir, txn_->staging_name, txn_->claims.empty() ? txn_->names.Lock() : "");
}

OutputSet::~OutputSet() {
  ActiveSets().erase(out_);
  if (!committed_) Abandon();
}

void OutputSet::Abandon() {
  if (txn_) {
    if (txn_->interrupt_handle) UnregisterInterruptFolder(txn_->interrupt_handle);
    if (!txn_->staging_name.empty()) RemoveTreeAt(txn_->dir.get(), txn_->staging_name);
    txn_->Finish(out_, {});
    txn_.reset();
  }
  RemoveEmptyFolders(created_parents_);  // a refused or failed run leaves no new folders behind
}

}  // namespace al
