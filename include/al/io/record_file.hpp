// A byte range of an open file that can be read again later. A PLY scene keeps its binary vertex
// records here instead of a second in-memory copy, so the byte-exact writer works without doubling
// the memory of big scenes (issue #7: refine must stay under 3x the scene file size). The file
// descriptor stays open, so replacing or renaming the path after loading does not change what is
// read; a file truncated in place is reported as an error, never read past its end.
#pragma once
#include <cstdint>
#include <string>

namespace al {

class RecordFile {
 public:
  // Opens path and remembers [offset, offset + bytes). Throws al::FileError when it cannot be opened.
  RecordFile(const std::string& path, std::uint64_t offset, std::uint64_t bytes);
  ~RecordFile();
  RecordFile(const RecordFile&) = delete;
  RecordFile& operator=(const RecordFile&) = delete;

  const std::string& path() const { return path_; }
  std::uint64_t size() const { return bytes_; }

  // Copies [begin, begin + length) of the range into out. Throws al::FileError on a short read.
  void Read(std::uint64_t begin, std::uint64_t length, char* out) const;

 private:
  std::string path_;
  int fd_ = -1;
  std::uint64_t offset_ = 0, bytes_ = 0;
};

}  // namespace al
