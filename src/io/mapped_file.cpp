#include "src/io/mapped_file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <future>
#include <mutex>
#include <vector>

#include "al/core/error.hpp"
#include "al/core/input_file.hpp"

namespace al::io {

MappedFile::MappedFile(const std::string& path) {
  const int fd = OpenRegularFile(path);
  struct stat st {};
  ::fstat(fd, &st);
  size_ = static_cast<std::size_t>(st.st_size);
  if (size_ > 0) {
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (p == MAP_FAILED) {
      const int err = errno;
      ::close(fd);
      throw FileError(path, std::string("cannot memory-map: ") + std::strerror(err));
    }
    // One sequential pass: ask the kernel to read ahead aggressively.
    ::madvise(p, size_, MADV_SEQUENTIAL);
    ::madvise(p, size_, MADV_WILLNEED);
    data_ = static_cast<const unsigned char*>(p);
  }
  ::close(fd);  // the mapping stays valid after close
}

MappedFile::~MappedFile() {
  if (data_) ::munmap(const_cast<unsigned char*>(data_), size_);
}

namespace {

// The unmappings under way; a finished one is dropped when the next starts, the rest are waited
// for when the program ends (the futures' destructors).
struct Unmappings {
  std::mutex mutex;
  std::vector<std::future<void>> running;
};

Unmappings& Pending() {
  static Unmappings pending;
  return pending;
}

}  // namespace

void UnmapInBackground(std::unique_ptr<MappedFile> file) {
  Unmappings& pending = Pending();
  const std::lock_guard<std::mutex> lock(pending.mutex);
  std::erase_if(pending.running, [](const std::future<void>& f) {
    return f.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
  });
  // The task owns the file alone, so the unmapping always happens on its thread.
  pending.running.push_back(std::async(std::launch::async, [owned = std::move(file)]() mutable { owned.reset(); }));
}

}  // namespace al::io
