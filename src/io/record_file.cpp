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

bool RecordFile::CopyTo(int out_fd, std::uint64_t begin, std::uint64_t length) const {
  if (begin > bytes_ || length > bytes_ - begin)
    throw FileError(path_, "record range past the end of the vertex data");
  auto in_offset = static_cast<off_t>(offset_ + begin);
  std::uint64_t done = 0;
  while (done < length) {
    const ssize_t got = ::copy_file_range(fd_, &in_offset, out_fd, nullptr, length - done, 0);
    if (got < 0 && errno == EINTR) continue;
    // Not supported here (old kernel, file systems that refuse, special files): nothing is
    // written yet on the first call, so the caller can copy through memory instead.
    if (got < 0 && done == 0 && (errno == ENOSYS || errno == EXDEV || errno == EINVAL || errno == EOPNOTSUPP))
      return false;
    if (got <= 0)
      throw FileError(path_, got == 0 ? "file shrank after it was loaded (vertex records missing)"
                                      : std::string("copying records failed: ") + std::strerror(errno));
    done += static_cast<std::uint64_t>(got);
  }
  return true;
}

}  // namespace al
