// The lock and claim record of an output folder: ".NAME.al-lock" beside --out (".al-lock" inside
// it when the set is staged there). Every writer holds flock(LOCK_EX) on it for its whole run, so
// two writers never interleave; the holder records in it what it creates — its transaction
// folders, whose names carry a random token, and the journals it claims. The file is this user's
// and writable by nobody else (checked when opened), so a neighbour cannot forge a record, and the
// next writer acts only on recorded names: a look-alike folder is left alone.
#pragma once
#include <sys/types.h>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace al::output_set {

namespace fs = std::filesystem;

struct LockRecord {
  pid_t pid = 0;
  std::string staging, commit;        // the holder's transaction folders (names beside the lock)
  std::vector<std::string> journals;  // append-only files of --out the holder claimed

  std::string ToText() const;
  // nullopt for anything that is not a record this code wrote (empty, torn, foreign).
  static std::optional<LockRecord> Parse(const std::string& text);
};

class OutputLock {
 public:
  using Notice = std::function<void(const std::string&)>;
  // Opens (creating it 0600) and locks dirfd/name; `shown` names it in messages and `out` the
  // folder it guards. When another writer holds it: waits, telling `notice` once, or (wait ==
  // false) refuses. Throws al::Error (exit 2) when the file is a link, not a regular file, or not
  // this user's alone.
  OutputLock(int dirfd, std::string name, fs::path shown, const fs::path& out, bool wait, const Notice& notice);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  // What the previous holder recorded (a run that was killed or failed), if anything.
  const std::optional<LockRecord>& previous() const { return previous_; }
  // Replaces the record in place (padded, so a kill mid-way never leaves a longer, older tail).
  void Record(const LockRecord& record);
  // Unlinks the lock file while still holding it, then releases it: a waiter that gets the lock
  // next finds the name gone and locks a fresh file instead.
  void Remove();

 private:
  int dirfd_;
  std::string name_;
  fs::path shown_;
  int fd_ = -1;
  std::size_t written_ = 0;
  std::optional<LockRecord> previous_;
  bool TryOnce(const fs::path& out, bool wait, const Notice& notice);
};

// The record of dirfd/name without taking the lock (info --verify); `busy`: a writer holds it now.
std::optional<LockRecord> PeekLock(int dirfd, const std::string& name, bool& busy);

}  // namespace al::output_set
