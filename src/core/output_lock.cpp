#include "src/core/output_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <nlohmann/json.hpp>

#include "al/core/error.hpp"
#include "src/core/folder_fd.hpp"

namespace al::output_set {
namespace {

constexpr const char* kFormat = "al-refine output lock";
constexpr std::size_t kMaxRecordBytes = 1 << 20;

std::string ReadAll(int fd) {
  std::string text;
  char buffer[4096];
  for (off_t at = 0; text.size() < kMaxRecordBytes;) {
    const ssize_t got = ::pread(fd, buffer, sizeof buffer, at);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    text.append(buffer, static_cast<std::size_t>(got));
    at += got;
  }
  return text;
}

// Why the file at dirfd/name cannot be this folder's lock, or "" when it can.
std::string Unfit(const struct stat& st) {
  if (!S_ISREG(st.st_mode)) return "is not a regular file";
  if (st.st_uid != ::geteuid()) return "belongs to another user (uid " + std::to_string(st.st_uid) + ")";
  if (st.st_mode & (S_IWGRP | S_IWOTH)) return "can be written by other users";
  return "";
}

std::string HolderOf(int fd) {
  const auto record = LockRecord::Parse(ReadAll(fd));
  return record && record->pid > 0 ? "another al-refine (pid " + std::to_string(record->pid) + ")"
                                   : "another al-refine";
}

}  // namespace

std::string LockRecord::ToText() const {
  return nlohmann::json{{"format", kFormat}, {"pid", pid}, {"staging", staging}, {"commit", commit},
                        {"journals", journals}}
             .dump() +
         "\n";
}

std::optional<LockRecord> LockRecord::Parse(const std::string& text) {
  const auto j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object() || j.value("format", "") != kFormat) return std::nullopt;
  LockRecord r;
  try {
    r.pid = j.at("pid").get<pid_t>();
    r.staging = j.at("staging").get<std::string>();
    r.commit = j.at("commit").get<std::string>();
    r.journals = j.at("journals").get<std::vector<std::string>>();
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return r;
}

OutputLock::OutputLock(int dirfd, std::string name, fs::path shown, const fs::path& out, bool wait,
                       const Notice& notice)
    : dirfd_(dirfd), name_(std::move(name)), shown_(std::move(shown)) {
  for (int attempt = 0; !TryOnce(out, wait, attempt == 0 ? notice : Notice()); ++attempt) {
  }
  previous_ = LockRecord::Parse(ReadAll(fd_));
}

// One attempt: open, check, lock; false when the file was removed while this run waited for it.
bool OutputLock::TryOnce(const fs::path& out, bool wait, const Notice& notice) {
  const int fd = ::openat(dirfd_, name_.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0600);
  if (fd < 0)
    throw FileError(shown_.string(), std::string("cannot open the output folder's lock file: ") +
                                         (errno == ELOOP ? "it is a symbolic link" : std::strerror(errno)));
  UniqueFd owned(fd);
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw FileError(shown_.string(), std::string("cannot stat: ") + std::strerror(errno));
  if (const std::string why = Unfit(st); !why.empty())
    throw FileError(shown_.string(), "the lock file of " + out.string() + " " + why +
                                         ": somebody else claims this output folder; refusing (remove it if it is yours)");
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno != EWOULDBLOCK) throw FileError(shown_.string(), std::string("cannot lock: ") + std::strerror(errno));
    const std::string holder = HolderOf(fd);
    if (!wait)
      throw Error(out.string() + ": " + holder + " is writing into it; refusing (--no-wait); run again when it is done",
                  ExitCode::kBadInput);
    if (notice) notice("waiting for " + holder + ", which is writing into " + out.string());
    while (::flock(fd, LOCK_EX) != 0)
      if (errno != EINTR) throw FileError(shown_.string(), std::string("cannot lock: ") + std::strerror(errno));
  }
  const auto now = StatAt(dirfd_, name_);
  if (!now || now->st_ino != st.st_ino || now->st_dev != st.st_dev) return false;  // removed meanwhile
  fd_ = owned.release();
  return true;
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);
}

void OutputLock::Record(const LockRecord& record) {
  std::string text = record.ToText();
  if (text.size() < written_) text.append(written_ - text.size(), ' ');  // JSON ignores trailing blanks
  const ssize_t put = ::pwrite(fd_, text.data(), text.size(), 0);
  if (put != static_cast<ssize_t>(text.size()))
    throw FileError(shown_.string(), std::string("cannot write the lock record: ") +
                                         (put < 0 ? std::strerror(errno) : "short write (disk full?)"));
  written_ = std::max(written_, text.size());
}

void OutputLock::Remove() {
  if (fd_ < 0) return;
  ::unlinkat(dirfd_, name_.c_str(), 0);
  ::close(fd_);
  fd_ = -1;
}

std::optional<LockRecord> PeekLock(int dirfd, const std::string& name, bool& busy) {
  busy = false;
  const UniqueFd fd(::openat(dirfd, name.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC));
  struct stat st {};
  if (!fd || ::fstat(fd.get(), &st) != 0 || !Unfit(st).empty()) return std::nullopt;
  busy = ::flock(fd.get(), LOCK_SH | LOCK_NB) != 0;
  return LockRecord::Parse(ReadAll(fd.get()));
}

}  // namespace al::output_set
