// SIGINT, SIGTERM and SIGHUP end a run cleanly: the staging folders of its output sets are removed
// and the process exits with 128 + the signal's number (docs/reliability.md). The CLI installs it
// before any thread starts; a library user (the Python module) keeps its own signal handling, and
// then the registry below is only bookkeeping.
#pragma once
#include <cstddef>
#include <mutex>
#include <string>

namespace al {

// Blocks the three signals in the calling thread (and so in every thread started after it) and
// starts the thread that waits for them. Call once, first thing in main.
void InstallInterruptCleanup();

// A folder to remove if the process is interrupted: dirfd/name (dirfd must stay open until
// Unregister), and the lock file dirfd/lock to remove with it ("" when the lock must stay: its
// record claims journals the next run resumes). Returns a handle for the two calls below.
std::size_t RegisterInterruptFolder(int dirfd, std::string name, std::string lock);
void SetInterruptLock(std::size_t handle, std::string lock);
void UnregisterInterruptFolder(std::size_t handle);

// While held, an interrupt waits: a commit that has started moving a set into place finishes
// (the process then exits with 128 + n, the new set complete).
std::unique_lock<std::recursive_mutex> HoldInterrupts();

}  // namespace al
