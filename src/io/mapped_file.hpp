// Read-only memory mapping of a whole file (RAII). Parsers take (data, size) views of it, so the
// same code also parses in-memory buffers (fuzzing, tests).
#pragma once
#include <cstddef>
#include <memory>
#include <string>

namespace al::io {

class MappedFile {
 public:
  // Maps `path` read-only; throws al::Error "<path>: <problem>" when it cannot be opened or mapped.
  explicit MappedFile(const std::string& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  const unsigned char* data() const { return data_; }
  std::size_t size() const { return size_; }

 private:
  const unsigned char* data_ = nullptr;  // nullptr for an empty file (mmap of 0 bytes is invalid)
  std::size_t size_ = 0;
};

// Unmaps the file on a helper thread (joined at the latest when the program ends): unmapping a
// decoded 700 MB scene takes ~25 ms, which the loading thread spends on the next input instead.
void UnmapInBackground(std::unique_ptr<MappedFile> file);

}  // namespace al::io
