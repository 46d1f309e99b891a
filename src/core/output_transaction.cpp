// The filesystem steps of an output-set commit: the atomic exchange, the journaled per-entry
// commit with its roll-forward, and the look-alike folders left alone. Everything acts through
// descriptors on folders this run (or a recorded earlier run) made, never through a link.
#include <fcntl.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <initializer_list>

#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "src/core/folder_fd.hpp"
#include "src/core/output_set_internal.hpp"

namespace al::output_set {
namespace {

[[noreturn]] void Fail(const fs::path& path, const std::string& what) {
  throw FileError(path.string(), what + ": " + std::strerror(errno));
}

void RemoveOrThrow(int dirfd, const std::string& name, const fs::path& shown) {
  if (!RemoveTreeAt(dirfd, name)) Fail(shown, "cannot remove (replacing an earlier al-refine output)");
}

void MoveOrThrow(int from_fd, int to_fd, const std::string& name, const fs::path& shown) {
  if (::renameat(from_fd, name.c_str(), to_fd, name.c_str()) != 0) Fail(shown, "cannot move output into place");
}

// The names in a commit folder's removal list (written by the run that made the folder).
std::vector<std::string> RemovalList(int commit_fd) {
  std::vector<std::string> names;
  const int fd = ::openat(commit_fd, kRemoveList, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return names;
  std::string text;
  char buffer[4096];
  for (ssize_t got; (got = ::read(fd, buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<std::size_t>(got));
  ::close(fd);
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t nl = std::min(text.find('\n', at), text.size());
    const std::string line = text.substr(at, nl - at);
    if (!line.empty() && line.find('/') == std::string::npos && line != "." && line != "..") names.push_back(line);
    at = nl + 1;
  }
  return names;
}

}  // namespace

std::vector<std::string> LookAlikes(const fs::path& dir, const TransactionNames& names) {
  std::vector<std::string> found;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    if (n.rfind(names.prefix, 0) != 0) continue;
    const std::string rest = n.substr(names.prefix.size());
    for (const char* kind : {"al-staging-", "al-commit-", "eval-tmp-"})
      if (rest.rfind(kind, 0) == 0 && rest.size() > std::strlen(kind)) found.push_back(n);
  }
  std::sort(found.begin(), found.end());
  return found;
}

void RollForward(int dirfd, const fs::path& dir, const std::string& commit_name, const fs::path& out) {
  const fs::path shown = dir / commit_name;
  const UniqueFd commit = OpenFolderAt(dirfd, commit_name);
  if (!commit) Fail(shown, "cannot open the commit folder");
  std::error_code ec;
  fs::create_directories(out, ec);
  const UniqueFd target = OpenFolder(out);
  if (!target) Fail(out, "cannot open the output folder");
  // The old report goes first: from here until the new one lands, a reader sees no report.json
  // and knows the folder is in transition.
  const bool has_report = StatAt(commit.get(), "report.json").has_value();
  if (has_report) RemoveOrThrow(target.get(), "report.json", out / "report.json");
  for (const auto& name : RemovalList(commit.get())) RemoveOrThrow(target.get(), name, out / name);
  for (const auto& name : EntriesAt(commit.get())) {
    if (name == "report.json") continue;
    RemoveOrThrow(target.get(), name, out / name);
    MoveOrThrow(commit.get(), target.get(), name, out / name);
  }
  if (has_report) MoveOrThrow(commit.get(), target.get(), "report.json", out / "report.json");
  RemoveTreeAt(dirfd, commit_name);
}

bool TryExchange(int dirfd, const std::string& staging, const fs::path& out, const std::vector<std::string>& journals,
                 const std::vector<std::string>& replaced) {
  const std::string out_name = out.filename().string();
  const UniqueFd old_fd = OpenFolderAt(dirfd, out_name), new_fd = OpenFolderAt(dirfd, staging);
  if (!old_fd || !new_fd) return false;
  std::vector<std::string> links;  // journals enter the new set as hard links: a kill never loses them
  bool linked = true;
  for (const auto& j : journals) {
    if (!IsOwnFileAt(old_fd.get(), j) || StatAt(new_fd.get(), j)) continue;
    linked = linked && ::linkat(old_fd.get(), j.c_str(), new_fd.get(), j.c_str(), 0) == 0;
    if (linked) links.push_back(j);
  }
  struct stat st {};
  if (::fstat(old_fd.get(), &st) == 0) ::fchmod(new_fd.get(), st.st_mode & 07777);
  if (!linked || ::renameat2(dirfd, staging.c_str(), dirfd, out_name.c_str(), RENAME_EXCHANGE) != 0) {
    for (const auto& l : links) ::unlinkat(new_fd.get(), l.c_str(), 0);
    return false;
  }
  // old_fd (now named `staging`) holds the previous set. Anything the commit did not decide to
  // replace appeared during the commit: move it back rather than delete what al-refine did not write.
  bool kept_foreign = false;
  for (const auto& name : EntriesAt(old_fd.get())) {
    if (std::count(replaced.begin(), replaced.end(), name) || std::count(journals.begin(), journals.end(), name))
      continue;
    if (!StatAt(new_fd.get(), name)) ::renameat(old_fd.get(), name.c_str(), new_fd.get(), name.c_str());
    kept_foreign |= StatAt(old_fd.get(), name).has_value();
  }
  if (kept_foreign) {
    const std::string kept = out_name + ".al-kept-" + RandomToken();
    ::renameat2(dirfd, staging.c_str(), dirfd, kept.c_str(), RENAME_NOREPLACE);
  } else {
    RemoveTreeAt(dirfd, staging);
  }
  return true;
}

}  // namespace al::output_set
