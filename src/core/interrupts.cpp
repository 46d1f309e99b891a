#include "al/core/interrupts.hpp"

#include <pthread.h>
#include <signal.h>
#include <fcntl.h>
#include <unistd.h>

#include <map>
#include <thread>

#include "src/core/folder_fd.hpp"

namespace al {
namespace {

struct Registry {
  std::recursive_mutex commit;  // held by commits (HoldInterrupts); taken first by the signal thread
  std::mutex mutex;             // the folders
  struct Folder {
    int dirfd;
    std::string name, lock;
  };
  std::map<std::size_t, Folder> folders;
  std::size_t next = 1;
};

Registry& TheRegistry() {
  static Registry* registry = new Registry;  // never destroyed: the signal thread may outlive main
  return *registry;
}

const char* SignalName(int sig) {
  switch (sig) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "a signal";
  }
}

// Async-signal context is avoided altogether: the signals are blocked everywhere and this thread
// takes them with sigwait, so it may lock, allocate and remove folders.
[[noreturn]] void WaitForInterrupt(sigset_t set) {
  int sig = 0;
  while (::sigwait(&set, &sig) != 0) {
  }
  Registry& r = TheRegistry();
  std::lock_guard<std::recursive_mutex> commit(r.commit);
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& [handle, folder] : r.folders) {
    for (int attempt = 0; attempt < 5 && !output_set::RemoveTreeAt(folder.dirfd, folder.name); ++attempt) {
    }
    if (!folder.lock.empty()) ::unlinkat(folder.dirfd, folder.lock.c_str(), 0);  // ours: this process holds it
  }
  const bool removed = !r.folders.empty();
  const std::string message = std::string("al-refine: interrupted by ") + SignalName(sig) +
                              (removed ? "; the unfinished output was removed, --out is as it was\n" : "\n");
  (void)!::write(2, message.data(), message.size());
  ::_exit(128 + sig);
}

}  // namespace

void InstallInterruptCleanup() {
  sigset_t set;
  sigemptyset(&set);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set, sig);
  if (::pthread_sigmask(SIG_BLOCK, &set, nullptr) != 0) return;
  std::thread(WaitForInterrupt, set).detach();
}

std::size_t RegisterInterruptFolder(int dirfd, std::string name, std::string lock_name) {
  Registry& r = TheRegistry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.folders[r.next] = {dirfd, std::move(name), std::move(lock_name)};
  return r.next++;
}

void SetInterruptLock(std::size_t handle, std::string lock_name) {
  Registry& r = TheRegistry();
  std::lock_guard<std::mutex> lock(r.mutex);
  if (const auto it = r.folders.find(handle); it != r.folders.end()) it->second.lock = std::move(lock_name);
}

void UnregisterInterruptFolder(std::size_t handle) {
  Registry& r = TheRegistry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.folders.erase(handle);
}

std::unique_lock<std::recursive_mutex> HoldInterrupts() {
  return std::unique_lock<std::recursive_mutex>(TheRegistry().commit);
}

}  // namespace al
