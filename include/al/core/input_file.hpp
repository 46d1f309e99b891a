// Opening inputs: what is not a regular file is refused at once with exit 2 (a FIFO would block
// for ever, a character device never ends, a folder has no bytes), before any byte is read.
#pragma once
#include <cstdint>
#include <string>

namespace al {

// Whether a symbolic link in the path's last component is followed. Inputs the user names may be
// links; files al-refine finds inside an output folder are never followed (docs/reliability.md).
enum class Links { kFollow, kRefuse };

// An fd open for reading on a regular file (the caller closes it); throws al::Error naming the
// file and what it is ("is a FIFO, not a regular file") otherwise.
int OpenRegularFile(const std::string& path, Links links = Links::kFollow);

// The whole file; also refuses files over max_bytes (text inputs: cameras, manifests, masks).
std::string ReadInputFile(const std::string& path, std::uint64_t max_bytes = std::uint64_t(1) << 31,
                          Links links = Links::kFollow);

}  // namespace al
