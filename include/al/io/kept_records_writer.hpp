// Writes a header and the kept fixed-size records of a RecordFile to an open file, in parallel
// chunks at absolute offsets. Each chunk of the output is assembled in an aligned user buffer
// (records read with pread from the source, which a scene just loaded has in the page cache) and
// written with one pwrite, so both cores share the copying.
//
// Why direct I/O is tried: on some machines (virtual machines whose host backs guest memory
// lazily) the kernel's first touch of fresh page-cache pages dominates a big write: 557 MB of
// remaining.ply took 2.2 s buffered against 0.4 s written through with O_DIRECT (docs/benchmarks.md).
// Elsewhere (a slow disk, warm page cache) buffered writes are the faster, and on one machine the
// faster way changes during one file. kAdaptive times every chunk and writes each the way that
// is currently faster; a file system that refuses O_DIRECT gets buffered writes.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "al/io/record_file.hpp"

namespace al {

enum class RecordWriteMode { kAdaptive, kBuffered, kDirect };

struct KeptRecordsOptions {
  // Bytes per chunk; a multiple of kDirectAlignment (4096), at least one alignment unit.
  std::size_t chunk_bytes = std::size_t{4} << 20;
  // kAdaptive below this output size: buffered writes only (page cache, no device wait).
  std::uint64_t adaptive_min_bytes = std::uint64_t{64} << 20;
  // kDirect: every whole chunk through O_DIRECT where the file system takes it.
  RecordWriteMode mode = RecordWriteMode::kAdaptive;
};

struct KeptRecordsSummary {
  std::uint64_t bytes = 0;  // header + kept records
  std::uint64_t direct_bytes = 0;  // of those, written through O_DIRECT
};

inline constexpr std::size_t kDirectAlignment = 4096;

// Writes header then, in row order, every record i with keep[i] (record i is bytes
// [i * record_bytes, (i + 1) * record_bytes) of source) to out_fd from offset 0, and sets the file's
// size to exactly that. out_fd must be a regular file opened for writing, empty. Throws
// al::FileError (named after out_path) on a failed read or write.
KeptRecordsSummary WriteKeptRecords(int out_fd, const std::string& out_path, const std::string& header,
                                    const RecordFile& source, std::size_t record_bytes,
                                    const std::vector<bool>& keep, const KeptRecordsOptions& options = {});

}  // namespace al
