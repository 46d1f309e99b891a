#include "al/io/record_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "al/core/error.hpp"

namespace al {

RecordFile::RecordFile(const std::string& path, std::uint64_t offset, std::uint64_t bytes)
    : path_(path), offset_(offset), bytes_(bytes) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw FileError(path, std::string("cannot reopen for the writer: ") + std::strerror(errno));
}

RecordFile::~RecordFile() {
  if (fd_ >= 0) ::close(fd_);
}

void RecordFile::Read(std::uint64_t begin, std::uint64_t length, char* out) const {
  if (begin > bytes_ || length > bytes_ - begin)
    throw FileError(path_, "record range past the end of the vertex data");
  std::uint64_t done = 0;
  while (done < length) {
    const ssize_t got = ::pread(fd_, out + done, length - done, static_cast<off_t>(offset_ + begin + done));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0)
      throw FileError(path_, got == 0 ? "file shrank after it was loaded (vertex records missing)"
                                      : std::string("read failed: ") + std::strerror(errno));
    done += static_cast<std::uint64_t>(got);
  }
}

}  // namespace al
