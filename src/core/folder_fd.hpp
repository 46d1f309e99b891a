// Folder operations through descriptors (openat, unlinkat, renameat2, always O_NOFOLLOW): the
// output set acts on the folders it made this way, so that a link a neighbour planted under one
// of their names is removed, never followed (docs/reliability.md, "Threat model").
#pragma once
#include <sys/stat.h>
#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace al::output_set {

namespace fs = std::filesystem;

// An owned descriptor (closed on destruction).
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  ~UniqueFd();
  UniqueFd(UniqueFd&& other) noexcept : fd_(other.release()) {}
  UniqueFd& operator=(UniqueFd&& other) noexcept;
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  int get() const { return fd_; }
  explicit operator bool() const { return fd_ >= 0; }
  int release();

 private:
  int fd_ = -1;
};

// A folder, opened for *at() calls; invalid (check with bool) when the path's last component is a
// link or not a folder.
UniqueFd OpenFolder(const fs::path& dir);
UniqueFd OpenFolderAt(int dirfd, const std::string& name);

// The entry names of a folder (without "." and ".."), sorted.
std::vector<std::string> NamesAt(int dirfd);

// lstat of dirfd/name; nullopt when there is nothing under the name.
std::optional<struct stat> StatAt(int dirfd, const std::string& name);

// dirfd/name is a real folder (not a link) of this user: the only kind recovery acts on.
bool IsOwnFolderAt(int dirfd, const std::string& name);

// dirfd/name is a regular file (not a link) of this user.
bool IsOwnFileAt(int dirfd, const std::string& name);

// Removes dirfd/name and, when it is a folder, everything below it, descending only into real
// folders (a link is unlinked, never followed). True when nothing is left under the name.
bool RemoveTreeAt(int dirfd, const std::string& name);

// 16 hex digits from the kernel's random source: the claim in a transaction folder's name, which a
// neighbour cannot guess in advance.
std::string RandomToken();

// The process's file-mode creation mask, read without changing it (umask(2) would, for a moment,
// for every thread).
mode_t CurrentUmask();

}  // namespace al::output_set
