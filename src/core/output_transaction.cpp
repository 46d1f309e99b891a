// The filesystem steps of an output-set commit: finding killed runs' transaction folders, the
// atomic exchange, and the journaled per-entry commit with its roll-forward.
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <initializer_list>

#include "al/core/error.hpp"
#include "src/core/output_set_internal.hpp"

namespace al::output_set {
namespace {

// "<digits>" -> pid, else 0.
pid_t ParsePid(const std::string& s) {
  if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos) return 0;
  return static_cast<pid_t>(std::stol(s));
}

void Fail(const fs::path& path, const std::string& what, const std::error_code& ec) {
  throw FileError(path.string(), what + ": " + ec.message());
}

void RemoveAllOrThrow(const fs::path& path) {
  std::error_code ec;
  fs::remove_all(path, ec);
  if (ec) Fail(path, "cannot remove (replacing an earlier al-refine output)", ec);
}

std::vector<std::string> ReadNames(const fs::path& file) {
  std::vector<std::string> names;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line.find('/') == std::string::npos && line != "." && line != "..") names.push_back(line);
  return names;
}

}  // namespace

bool ProcessAlive(pid_t pid) {
  if (pid <= 0) return true;  // unknown: keep
  return ::kill(pid, 0) == 0 || errno == EPERM;
}

namespace {

// Entries of `dir` named base + kind + PID.
void FindIn(const fs::path& dir, const std::string& base, std::initializer_list<const char*> kinds, std::vector<Stale>& found) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    if (n.rfind(base, 0) != 0) continue;
    const std::string rest = n.substr(base.size());
    for (const char* kind : kinds) {
      const std::string k = kind;
      if (rest.rfind(k, 0) != 0) continue;
      if (const pid_t pid = ParsePid(rest.substr(k.size())); pid > 0)
        found.push_back({it->path(), pid, k == "al-commit-"});
    }
  }
}

}  // namespace

std::vector<Stale> FindTransactions(const fs::path& parent, const std::string& name) {
  std::vector<Stale> found;
  FindIn(parent, "." + name + ".", {"al-staging-", "al-commit-", "eval-tmp-"}, found);
  FindIn(parent / name, ".", {"al-staging-", "al-commit-"}, found);  // staged inside --out (StagesInside)
  std::sort(found.begin(), found.end(), [](const Stale& a, const Stale& b) { return a.path < b.path; });
  return found;
}

void RollForward(const fs::path& commit_dir, const fs::path& out) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) Fail(out, "cannot create output folder", ec);
  // The old report goes first: from here until the new one lands, a reader sees no report.json
  // and knows the folder is in transition.
  if (fs::exists(commit_dir / "report.json") && fs::exists(out / "report.json")) RemoveAllOrThrow(out / "report.json");
  for (const auto& name : ReadNames(commit_dir / kRemoveList)) RemoveAllOrThrow(out / name);
  for (const auto& name : Entries(commit_dir)) {
    if (name == "report.json") continue;
    RemoveAllOrThrow(out / name);
    fs::rename(commit_dir / name, out / name, ec);
    if (ec) Fail(out / name, "cannot move output into place", ec);
  }
  if (fs::exists(commit_dir / "report.json")) {
    fs::rename(commit_dir / "report.json", out / "report.json", ec);
    if (ec) Fail(out / "report.json", "cannot move output into place", ec);
  }
  fs::remove_all(commit_dir, ec);
}

bool TryExchange(const fs::path& staging, const fs::path& out, const std::vector<std::string>& journals,
                 const std::vector<std::string>& replaced) {
  std::vector<fs::path> links;  // journals enter the new set as hard links: a kill never loses them
  bool linked = true;
  for (const auto& j : journals) {
    if (!fs::exists(out / j) || fs::exists(staging / j)) continue;
    linked = linked && ::link((out / j).c_str(), (staging / j).c_str()) == 0;
    if (linked) links.push_back(staging / j);
  }
  struct stat st {};
  if (::stat(out.c_str(), &st) == 0) ::chmod(staging.c_str(), st.st_mode & 07777);
  if (!linked || ::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, out.c_str(), RENAME_EXCHANGE) != 0) {
    for (const auto& l : links) ::unlink(l.c_str());
    return false;
  }
  // `staging` now holds the previous set. Anything the commit did not decide to replace appeared
  // during the commit: move it back rather than delete what al-refine did not write.
  bool kept_foreign = false;
  for (const auto& name : Entries(staging)) {
    if (std::count(replaced.begin(), replaced.end(), name) || std::count(journals.begin(), journals.end(), name))
      continue;
    std::error_code ec;
    if (!fs::exists(out / name)) fs::rename(staging / name, out / name, ec);
    kept_foreign |= fs::exists(staging / name);
  }
  std::error_code ec;
  if (kept_foreign) {
    fs::rename(staging, fs::path(out.string() + ".al-kept-" + std::to_string(::getpid())), ec);
  } else {
    fs::remove_all(staging, ec);
  }
  return true;
}

DirLock::DirLock(const fs::path& dir) {
  fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ >= 0) ::flock(fd_, LOCK_EX);
}

DirLock::~DirLock() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace al::output_set
