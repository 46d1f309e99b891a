// Manifests of output sets: what a run wrote (BuildManifest), what an earlier run owns
// (ReadOwnership) and whether a folder still holds what its report says (VerifyOutputSet).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>

#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/core/output_set.hpp"
#include "al/core/report.hpp"
#include "src/core/output_set_internal.hpp"

namespace al {
namespace output_set {
namespace {

constexpr std::uintmax_t kHashLimit = std::uintmax_t(64) << 20;  // hashing more costs seconds

std::string Relative(const fs::path& file, const fs::path& root) {
  return file.lexically_relative(root).generic_string();
}

std::string TopOf(const std::string& rel) { return rel.substr(0, rel.find('/')); }

// report.json of an output folder: read only when it is a regular file (a FIFO planted there
// must not block) of this user (a neighbour's forged manifest owns nothing), never through a link.
std::optional<nlohmann::json> ReadReport(const fs::path& file, bool only_ours) {
  const auto st = StatAt(AT_FDCWD, file.string());
  if (!st || !S_ISREG(st->st_mode) || (only_ours && st->st_uid != ::geteuid())) return std::nullopt;
  try {
    return nlohmann::json::parse(ReadInputFile(file.string(), std::uint64_t(1) << 30, Links::kRefuse));
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace

std::vector<std::string> EntriesAt(int dirfd) {
  std::vector<std::string> names = NamesAt(dirfd);
  names.erase(std::remove_if(names.begin(), names.end(), IsControlFile), names.end());
  return names;
}

std::vector<std::string> Entries(const fs::path& dir) {
  const UniqueFd fd = OpenFolder(dir);
  return fd ? EntriesAt(fd.get()) : std::vector<std::string>{};
}

Ownership ReadOwnership(const fs::path& out) {
  Ownership own;
  const auto report = ReadReport(out / "report.json", /*only_ours=*/true);
  if (!report || !report->is_object() || !report->contains("command") || !report->contains("version")) return own;
  own.report_is_ours = true;
  const auto manifest = report->find("manifest");
  if (manifest == report->end() || !manifest->is_object() || !manifest->contains("files")) return own;
  for (const auto& f : (*manifest)["files"]) {
    if (!f.is_object() || !f.contains("path") || !f["path"].is_string()) continue;
    const std::string path = f["path"].get<std::string>();
    if (path.empty() || path.find("..") != std::string::npos || path[0] == '/') continue;
    own.files.insert(path);
    if (f.value("append_only", false)) own.journals.insert(path);
  }
  return own;
}

namespace {

// A file the manifest lists that is still what al-refine wrote there: a regular file of this user.
bool OwnedFile(const Ownership& own, const fs::path& out, const fs::path& file) {
  const auto st = StatAt(AT_FDCWD, file.string());
  return st && S_ISREG(st->st_mode) && st->st_uid == ::geteuid() && own.files.count(Relative(file, out));
}

}  // namespace

bool Owned(const Ownership& own, const fs::path& out, const std::string& top) {
  const fs::path entry = out / top;
  const auto st = StatAt(AT_FDCWD, entry.string());
  if (!st || st->st_uid != ::geteuid() || S_ISLNK(st->st_mode)) return false;
  if (top == "report.json") return own.report_is_ours && S_ISREG(st->st_mode);
  if (S_ISREG(st->st_mode)) return own.files.count(top) || own.journals.count(top);
  if (!S_ISDIR(st->st_mode)) return false;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(entry, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_directory(ec) && !it->is_symlink(ec)) continue;
    if (!OwnedFile(own, out, it->path())) return false;
  }
  return !ec;
}

nlohmann::json BuildManifest(const fs::path& staging, const fs::path& out, const std::vector<std::string>& journals) {
  std::vector<std::pair<std::string, fs::path>> files;
  for (fs::recursive_directory_iterator it(staging), end; it != end; ++it) {
    const std::string rel = Relative(it->path(), staging);
    if (IsControlFile(TopOf(rel))) continue;
    if (it->is_regular_file() && !it->is_symlink()) files.emplace_back(rel, it->path());
  }
  std::sort(files.begin(), files.end());
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [rel, path] : files) {
    if (rel == "report.json") continue;  // written after its manifest
    const auto bytes = fs::file_size(path);
    nlohmann::json f = {{"path", rel}, {"bytes", bytes}};
    if (bytes <= kHashLimit) f["sha256"] = Sha256File(path);
    list.push_back(std::move(f));
  }
  for (const auto& name : journals) {
    std::error_code ec;
    const auto bytes = fs::file_size(out / name, ec);
    if (ec) continue;
    nlohmann::json f = {{"path", name}, {"bytes", bytes}, {"append_only", true}};
    if (bytes <= kHashLimit) f["sha256"] = Sha256File(out / name, bytes, Links::kRefuse);
    list.push_back(std::move(f));
  }
  return {{"version", 1}, {"files", list},
          {"note", "report.json is written last; a file missing or differing from this list means the set is "
                   "not the one this report describes (`al-refine info --verify DIR`)"}};
}

}  // namespace output_set

namespace {

using namespace output_set;

// A manifest path that stays inside the set ("a/b.png", never "/x", "../x" or "a/../../x").
bool SafeRelative(const std::string& rel) {
  if (rel.empty() || rel[0] == '/' || rel.find('\0') != std::string::npos) return false;
  for (const auto& part : fs::path(rel))
    if (part == ".." || part == "." || part.empty()) return false;
  return true;
}

// A folder on the way to dir/rel is a link: the file is not where al-refine wrote it.
bool ThroughLink(const fs::path& dir, const std::string& rel) {
  fs::path at = dir;
  const fs::path parts(rel);
  for (auto it = parts.begin(); it != parts.end() && std::next(it) != parts.end(); ++it) {
    at /= *it;
    const auto st = StatAt(AT_FDCWD, at.string());
    if (st && S_ISLNK(st->st_mode)) return true;
  }
  return false;
}

// The file's hash, "" when it cannot be read as a regular file any more (swapped meanwhile).
std::string HashOrEmpty(const fs::path& file, std::uintmax_t bytes) {
  try {
    return Sha256File(file, bytes, Links::kRefuse);
  } catch (const Error&) {
    return "";
  }
}

// Problems of one manifest entry (none when the file is as listed).
void CheckEntry(const fs::path& dir, const nlohmann::json& f, OutputSetStatus& status, bool& grown) {
  if (!f.is_object() || !f.contains("path") || !f["path"].is_string() ||
      !SafeRelative(f["path"].get<std::string>())) {
    status.problems.push_back("manifest entry " + f.dump().substr(0, 80) + ": not a file path inside the folder");
    return;
  }
  const std::string rel = f["path"].get<std::string>();
  const bool append_only = f.value("append_only", false);
  const auto bytes_field = f.find("bytes");
  const std::uintmax_t bytes =
      bytes_field != f.end() && bytes_field->is_number_unsigned() ? bytes_field->get<std::uintmax_t>() : 0;
  std::error_code ec;
  if (ThroughLink(dir, rel)) {
    status.problems.push_back(rel + ": reached through a symbolic link (not what al-refine wrote)");
    return;
  }
  if (!fs::is_regular_file(fs::symlink_status(dir / rel, ec))) {  // never hash a FIFO or a device
    status.problems.push_back(rel + ": missing");
    return;
  }
  const auto size = fs::file_size(dir / rel, ec);
  if (ec) {
    status.problems.push_back(rel + ": missing");
    return;
  }
  if (append_only ? size < bytes : size != bytes) {
    status.problems.push_back(rel + ": " + std::to_string(size) + " bytes, the manifest says " + std::to_string(bytes));
    return;
  }
  const auto sha = f.find("sha256");
  if (sha != f.end() && (!sha->is_string() || HashOrEmpty(dir / rel, bytes) != sha->get<std::string>())) {
    status.problems.push_back(rel + ": content differs from the manifest (SHA-256)");
    return;
  }
  if (size > bytes) grown = true;
}

}  // namespace

nlohmann::json OutputSetStatus::ToJson() const {
  return {{"state", state}, {"command", command}, {"files", files}, {"problems", problems}, {"notes", notes}};
}

namespace {

// What the lock beside the folder (or inside it, for a set staged there) records: a writer at
// work now, an interrupted commit, a killed run's staging; and the look-alikes nobody recorded.
// True when a recorded commit was interrupted.
bool CheckTransactions(const fs::path& abs, OutputSetStatus& status) {
  bool interrupted = false;
  const std::pair<fs::path, std::string> places[] = {{abs.parent_path(), "." + abs.filename().string() + "."},
                                                     {abs, "."}};
  for (const auto& [dir, prefix] : places) {
    const TransactionNames names{prefix};
    const UniqueFd fd = OpenFolder(dir);
    if (!fd) continue;
    bool busy = false;
    const auto record = PeekLock(fd.get(), names.Lock(), busy);
    if (busy)
      status.notes.push_back("an al-refine run is writing into it now" +
                             (record ? " (pid " + std::to_string(record->pid) + ")" : std::string()));
    if (record && !busy && !record->commit.empty() && IsOwnFolderAt(fd.get(), record->commit)) {
      status.problems.push_back(record->commit + ": a commit was interrupted; the next run into this folder finishes it");
      interrupted = true;
    }
    if (record && !busy && !record->staging.empty() && IsOwnFolderAt(fd.get(), record->staging))
      status.problems.push_back(record->staging + ": staging of a killed run; the next run into this folder removes it");
    for (const auto& n : LookAlikes(dir, names))
      if (!record || (n != record->staging && n != record->commit))
        status.notes.push_back(n + ": looks like al-refine's bookkeeping, but no al-refine run recorded it; left alone");
  }
  return interrupted;
}

}  // namespace

OutputSetStatus VerifyOutputSet(const fs::path& dir) {
  const fs::path abs = fs::weakly_canonical(fs::absolute(dir));
  const auto report = ReadReport(abs / "report.json", /*only_ours=*/false);
  OutputSetStatus status = VerifyManifest(report ? report->dump() : std::string(), abs);
  const auto st = StatAt(AT_FDCWD, (abs / "report.json").string());
  if (st && !S_ISREG(st->st_mode)) status.problems.back() = "report.json is not a regular file";
  OutputSetStatus transactions;
  if (CheckTransactions(abs, transactions) && !report) status.state = "incomplete";
  status.problems.insert(status.problems.end(), transactions.problems.begin(), transactions.problems.end());
  status.notes = transactions.notes;
  return status;
}

OutputSetStatus VerifyManifest(const std::string& report_text, const fs::path& dir) {
  OutputSetStatus status;
  const nlohmann::json report = nlohmann::json::parse(report_text, nullptr, /*allow_exceptions=*/false);
  if (report.is_discarded() || !report.is_object()) {
    status.state = "not_a_set";
    status.problems.push_back("no readable report.json");
    return status;
  }
  const auto command = report.find("command");
  if (command != report.end() && command->is_string()) status.command = command->get<std::string>();
  const auto manifest = report.find("manifest");
  const nlohmann::json* files = nullptr;
  if (manifest != report.end() && manifest->is_object() && manifest->contains("files") &&
      (*manifest)["files"].is_array())
    files = &(*manifest)["files"];
  if (!files) {
    status.state = "not_a_set";
    status.problems.push_back("report.json has no manifest (an older al-refine?)");
    return status;
  }
  bool grown = false;
  for (const auto& f : *files) {
    ++status.files;
    CheckEntry(dir, f, status, grown);
  }
  status.state = !status.problems.empty() ? "incomplete" : grown ? "extended" : "complete";
  return status;
}

}  // namespace al
