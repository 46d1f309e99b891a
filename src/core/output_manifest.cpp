// Manifests of output sets: what a run wrote (BuildManifest), what an earlier run owns
// (ReadOwnership) and whether a folder still holds what its report says (VerifyOutputSet).
#include <fstream>

#include "al/core/error.hpp"
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

std::optional<nlohmann::json> ReadJson(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return std::nullopt;
  try {
    return nlohmann::json::parse(in);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace

std::vector<std::string> Entries(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    if (!IsControlFile(n)) names.push_back(n);
  }
  std::sort(names.begin(), names.end());
  return names;
}

Ownership ReadOwnership(const fs::path& out) {
  Ownership own;
  const auto report = ReadJson(out / "report.json");
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

bool Owned(const Ownership& own, const fs::path& out, const std::string& top) {
  if (top == "report.json") return own.report_is_ours;
  if (own.files.count(top) || own.journals.count(top)) return true;
  const fs::path entry = out / top;
  std::error_code ec;
  if (fs::is_symlink(entry, ec) || !fs::is_directory(entry, ec)) return false;
  for (fs::recursive_directory_iterator it(entry, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_directory(ec) && !it->is_symlink(ec)) continue;
    if (!own.files.count(Relative(it->path(), out))) return false;
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
    if (bytes <= kHashLimit) f["sha256"] = Sha256File(out / name, bytes);
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
  if (sha != f.end() && (!sha->is_string() || Sha256File(dir / rel, bytes) != sha->get<std::string>())) {
    status.problems.push_back(rel + ": content differs from the manifest (SHA-256)");
    return;
  }
  if (size > bytes) grown = true;
}

}  // namespace

nlohmann::json OutputSetStatus::ToJson() const {
  return {{"state", state}, {"command", command}, {"files", files}, {"problems", problems}};
}

OutputSetStatus VerifyOutputSet(const fs::path& dir) {
  const fs::path abs = fs::weakly_canonical(fs::absolute(dir));
  std::vector<std::string> stale;
  for (const Stale& s : FindTransactions(abs.parent_path(), abs.filename().string()))
    if (s.commit || !ProcessAlive(s.pid))
      stale.push_back(s.path.filename().string() + ": " +
                      (s.commit ? "a commit was interrupted; the next run into this folder finishes it"
                                : "staging of a killed run; the next run into this folder removes it"));
  const auto report = ReadJson(abs / "report.json");
  OutputSetStatus status = VerifyManifest(report ? report->dump() : std::string(), abs);
  if (!report && !stale.empty()) status.state = "incomplete";
  status.problems.insert(status.problems.end(), stale.begin(), stale.end());
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
