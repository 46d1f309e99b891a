// OutputSet (al/core/output_set.hpp): the checks before computing and the commit.
#include "al/core/output_set.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/report.hpp"
#include "src/core/output_set_internal.hpp"

namespace al {
namespace {

using namespace output_set;

bool g_force_outputs = false;
std::set<fs::path>& ActiveSets() {  // one staging folder per --out and process
  static std::set<fs::path> active;
  return active;
}

bool Contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
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

// Removes killed runs' staging, finishes their commits; returns the journals they had claimed.
std::vector<std::string> Recover(const fs::path& parent, const std::string& name, const fs::path& out) {
  std::vector<std::string> claimed;
  DirLock lock(parent);
  for (const Stale& s : FindTransactions(parent, name)) {
    if (ProcessAlive(s.pid) || s.pid == ::getpid()) continue;
    if (s.commit) {
      RollForward(s.path, out);
      continue;
    }
    std::ifstream in(s.path / kJournalClaims);
    for (std::string line; std::getline(in, line);)
      if (!line.empty()) claimed.push_back(line);
    std::error_code ec;
    fs::remove_all(s.path, ec);
  }
  return claimed;
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

std::string ForeignMessage(const std::string& flag, const fs::path& out, const std::vector<std::string>& names) {
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  return flag + " " + out.string() + " holds " + list +
         ", which no al-refine manifest there lists; refusing to replace what al-refine did not write "
         "(choose another " + flag + ", move it away, or pass --force)";
}

std::vector<std::string> ForeignCollisions(const std::vector<std::string>& names, const fs::path& out,
                                           const Ownership& own) {
  std::vector<std::string> foreign;
  std::error_code ec;
  for (const auto& n : names)
    if (fs::symlink_status(out / n, ec).type() != fs::file_type::not_found && !Owned(own, out, n))
      foreign.push_back(n);
  return foreign;
}

// Sets nested in this one (demo's refine_bk/, ...) name their inputs and outputs by staging paths;
// after the commit those live under --out, so their reports are made to say so.
void RewriteNestedReports(const fs::path& staging, const fs::path& out) {
  const std::string from = nlohmann::json(staging.string()).dump(), to = nlohmann::json(out.string()).dump();
  const std::string from_body = from.substr(1, from.size() - 2), to_body = to.substr(1, to.size() - 2);
  for (fs::recursive_directory_iterator it(staging), end; it != end; ++it) {
    if (it->path().filename() != "report.json" || it->path().parent_path() == staging) continue;
    std::ifstream in(it->path(), std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
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
  const fs::path rel = Canonical(fs::current_path(ec)).lexically_relative(out);
  return !ec && !rel.empty() && *rel.begin() != "..";
}

}  // namespace

void SetForceOutputs(bool force) { g_force_outputs = force; }
bool ForceOutputs() { return g_force_outputs; }

OutputSet::OutputSet(const fs::path& out, OutputSetOptions options) : options_(std::move(options)) {
  options_.force = options_.force || g_force_outputs;
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
    RemoveEmptyFolders(created_parents_);
    throw;
  }
  ActiveSets().insert(out_);
}

// The constructor's checks after --out's parent exists, and the staging folder.
void OutputSet::Open(const fs::path& out) {
  for (auto& name : Recover(parent_, name_, out_))  // a claim counts only for this run's own journals
    if (Contains(options_.journals, name)) adopted_journals_.push_back(std::move(name));
  Ownership own = ReadOwnership(out_);
  own.journals.insert(adopted_journals_.begin(), adopted_journals_.end());
  CheckInputs(options_, out_, own);
  std::vector<std::string> names = options_.planned;
  names.insert(names.end(), options_.journals.begin(), options_.journals.end());
  const auto foreign = ForeignCollisions(names, out_, own);
  if (!foreign.empty() && !options_.force) throw Error(ForeignMessage(options_.flag, out_, foreign));
  staging_ = TransactionPath("al-staging-");
  std::error_code ec;
  fs::remove_all(staging_, ec);
  if (!fs::create_directory(staging_, ec) || ec)
    throw Error(options_.flag + " " + out.string() + ": cannot create staging folder " +
                staging_.string() + ": " + ec.message());
}

OutputSet::~OutputSet() {
  ActiveSets().erase(out_);
  std::error_code ec;
  if (committed_) return;
  fs::remove_all(staging_, ec);
  RemoveEmptyFolders(created_parents_);  // a refused or failed run leaves no new folders behind
}

fs::path OutputSet::TransactionPath(const std::string& kind) const {
  const std::string pid = std::to_string(::getpid());
  return inside_ ? out_ / ("." + kind + pid) : parent_ / ("." + name_ + "." + kind + pid);
}

fs::path OutputSet::Journal(const std::string& name) {
  if (!Contains(options_.journals, name)) options_.journals.push_back(name);
  EnsureDirectory(out_);
  std::string claims;
  for (const auto& j : options_.journals) claims += j + "\n";
  WriteFileAtomically(staging_ / kJournalClaims, claims);
  return out_ / name;
}

nlohmann::json OutputSet::Commit(nlohmann::json report) {
  if (committed_) throw Error(options_.flag + " " + out_.string() + ": output set committed twice", ExitCode::kInternal);
  RewriteNestedReports(staging_, out_);
  report["manifest"] = BuildManifest(staging_, out_, options_.journals);
  WriteReport(staging_, report);
  DirLock lock(parent_);
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
  std::error_code ec;
  if (!fs::exists(out_)) {
    fs::rename(staging_, out_, ec);
    if (ec) throw FileError(out_.string(), "cannot move the output set into place: " + ec.message());
  } else if (inside_ || !kept_foreign.empty() || InsideCwd(out_) ||
             !TryExchange(staging_, out_, options_.journals, present)) {
    // Foreign files stay where they are: entries move one by one from a committed journal folder.
    std::string removals;
    for (const auto& n : old_owned) removals += n + "\n";
    WriteFileAtomically(staging_ / kRemoveList, removals);
    const fs::path commit = TransactionPath("al-commit-");
    fs::rename(staging_, commit, ec);
    if (ec) throw FileError(out_.string(), "cannot commit the output set: " + ec.message());
    RollForward(commit, out_);
  }
  committed_ = true;
  return report;
}

}  // namespace al
