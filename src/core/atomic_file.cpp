#include "al/core/atomic_file.hpp"

#include <ext/stdio_filebuf.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "al/core/error.hpp"
#include "src/core/folder_fd.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

// A fresh temporary beside `path`: created exclusively and never through a link, so a name planted
// in advance is neither followed nor truncated (another name is drawn instead).
int CreateTemporary(const fs::path& path, fs::path& tmp) {
  for (int attempt = 0; attempt < 8; ++attempt) {
    tmp = path.string() + ".tmp." + std::to_string(::getpid()) + "." + output_set::RandomToken().substr(0, 8);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0 || errno != EEXIST) return fd;
  }
  return -1;
}

}  // namespace

void WriteFileAtomically(const fs::path& path, const std::function<void(std::ostream&)>& write, bool binary) {
  fs::path tmp;
  const int fd = CreateTemporary(path, tmp);
  if (fd < 0) throw FileError(path.string(), std::string("cannot open for writing: ") + std::strerror(errno));
  bool ok = false;
  {
    __gnu_cxx::stdio_filebuf<char> buffer(fd, binary ? std::ios::out | std::ios::binary : std::ios::out);
    std::ostream out(&buffer);
    try {
      write(out);
    } catch (...) {
      buffer.close();
      ::unlink(tmp.c_str());
      throw;
    }
    out.flush();
    ok = static_cast<bool>(out) && buffer.close() != nullptr;
  }
  if (!ok) {
    ::unlink(tmp.c_str());
    throw FileError(path.string(), "write failed (disk full?)");
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    ::unlink(tmp.c_str());
    throw FileError(path.string(), "cannot rename temporary file into place");
  }
}

int FlushedDescriptor(std::ostream& os) {
  os.flush();
  auto* buffer = dynamic_cast<__gnu_cxx::stdio_filebuf<char>*>(os.rdbuf());
  return buffer != nullptr && os ? buffer->fd() : -1;
}

void WriteFileAtomically(const fs::path& path, const std::string& bytes) {
  WriteFileAtomically(path, [&](std::ostream& out) { out.write(bytes.data(), std::streamsize(bytes.size())); });
}

void EnsureDirectory(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw FileError(dir.string(), "cannot create output directory");
}

}  // namespace al
