#include "al/io/kept_records_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>

#include "al/core/error.hpp"

namespace al {
namespace {

struct Run {
  std::uint64_t out = 0, src = 0, bytes = 0;  // output offsets count the header
};

std::vector<Run> KeptRuns(const std::vector<bool>& keep, std::size_t record_bytes, std::uint64_t header) {
  std::vector<Run> runs;
  std::uint64_t out = header;
  for (std::size_t i = 0, n = keep.size(); i < n;) {
    if (!keep[i]) { ++i; continue; }
    std::size_t j = i;
    while (j < n && keep[j]) ++j;
    runs.push_back({out, std::uint64_t(i) * record_bytes, std::uint64_t(j - i) * record_bytes});
    out += runs.back().bytes;
    i = j;
  }
  return runs;
}

using AlignedBuffer = std::unique_ptr<char, decltype(&std::free)>;
AlignedBuffer NewBuffer(std::size_t bytes) {
  return AlignedBuffer(static_cast<char*>(std::aligned_alloc(kDirectAlignment, bytes)), &std::free);
}

double Now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

class ChunkWriter {
 public:
  ChunkWriter(int fd, const std::string& path, const std::string& header, const RecordFile& source,
              std::size_t record_bytes, const std::vector<bool>& keep, std::size_t chunk)
      : fd_(fd), path_(path), header_(header), source_(source), runs_(KeptRuns(keep, record_bytes, header.size())),
        chunk_(chunk) {
    total_ = runs_.empty() ? header.size() : runs_.back().out + runs_.back().bytes;
  }
  std::uint64_t total() const { return total_; }
  std::size_t chunks() const { return std::size_t((total_ + chunk_ - 1) / chunk_); }

  // Chunk c's bytes into buf (chunk_ bytes, aligned); returns how many to write (rounded up to the
  // alignment, zero-padded, when direct: the file's size is set exactly afterwards).
  std::size_t Fill(std::size_t c, char* buf, bool direct) const {
    const std::uint64_t lo = std::uint64_t(c) * chunk_, hi = std::min<std::uint64_t>(lo + chunk_, total_);
    if (lo < header_.size()) std::memcpy(buf, header_.data() + lo, std::min<std::uint64_t>(hi, header_.size()) - lo);
    auto it = std::upper_bound(runs_.begin(), runs_.end(), lo,
                               [](std::uint64_t x, const Run& r) { return x < r.out + r.bytes; });
    for (; it != runs_.end() && it->out < hi; ++it) {
      const std::uint64_t a = std::max(lo, it->out), b = std::min(hi, it->out + it->bytes);
      source_.Read(it->src + (a - it->out), b - a, buf + (a - lo));
    }
    std::size_t len = std::size_t(hi - lo);
    if (!direct) return len;
    const std::size_t padded = (len + kDirectAlignment - 1) / kDirectAlignment * kDirectAlignment;
    std::memset(buf + len, 0, padded - len);
    return padded;
  }

  // pwrite of a whole chunk; false (errno set) on failure.
  bool Write(std::size_t c, const char* buf, std::size_t len) const {
    std::uint64_t done = 0, at = std::uint64_t(c) * chunk_;
    while (done < len) {
      const ssize_t got = ::pwrite(fd_, buf + done, len - done, static_cast<off_t>(at + done));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) return false;
      done += std::uint64_t(got);
    }
    return true;
  }

  [[noreturn]] void Fail() const { throw FileError(path_, std::string("write failed: ") + std::strerror(errno)); }

  bool SetDirect(bool on) const {
    const int flags = ::fcntl(fd_, F_GETFL);
    return flags >= 0 && ::fcntl(fd_, F_SETFL, on ? (flags | O_DIRECT) : (flags & ~O_DIRECT)) == 0;
  }

  // Writes chunks [first, first + count) one after another; the seconds spent writing (not filling),
  // or infinity when direct I/O was refused (those chunks then written buffered).
  double TimeChunks(std::size_t first, std::size_t count, bool direct, char* buf) const {
    if (direct && !SetDirect(true)) direct = false;
    double seconds = 0;
    for (std::size_t c = first; c < first + count; ++c) {
      const std::size_t len = Fill(c, buf, direct);
      const double t = Now();
      if (Write(c, buf, len)) { seconds += Now() - t; continue; }
      if (!direct || errno != EINVAL || !SetDirect(false)) Fail();
      direct = false;  // the file system refuses O_DIRECT here: this chunk and the rest buffered
      seconds = std::numeric_limits<double>::infinity();
      if (!Write(c, buf, Fill(c, buf, false))) Fail();
    }
    return seconds;
  }

  void WriteAll(std::size_t first, bool direct) const;

 private:
  int fd_;
  const std::string& path_;
  const std::string& header_;
  const RecordFile& source_;
  std::vector<Run> runs_;
  std::size_t chunk_;
  std::uint64_t total_ = 0;
};

// Chunks [first, end) shared between the threads, each with its own buffer.
void ChunkWriter::WriteAll(std::size_t first, bool direct) const {
  const auto end = static_cast<std::int64_t>(chunks());
  std::exception_ptr error;
#pragma omp parallel
  {
    AlignedBuffer buf = NewBuffer(chunk_);
#pragma omp for schedule(dynamic, 1)
    for (auto c = static_cast<std::int64_t>(first); c < end; ++c) {
      try {
        if (!Write(std::size_t(c), buf.get(), Fill(std::size_t(c), buf.get(), direct))) Fail();
      } catch (...) {
#pragma omp critical(al_kept_records_error)
        if (!error) error = std::current_exception();
      }
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace

KeptRecordsSummary WriteKeptRecords(int out_fd, const std::string& out_path, const std::string& header,
                                    const RecordFile& source, std::size_t record_bytes,
                                    const std::vector<bool>& keep, const KeptRecordsOptions& options) {
  if (options.chunk_bytes < kDirectAlignment || options.chunk_bytes % kDirectAlignment != 0 || record_bytes == 0 ||
      std::uint64_t(keep.size()) * record_bytes > source.size())
    throw FileError(out_path, "kept-records writer: bad chunk size or record layout");
  const ChunkWriter writer(out_fd, out_path, header, source, record_bytes, keep, options.chunk_bytes);
  std::size_t next = 0;
  bool direct = options.mode == RecordWriteMode::kDirect;
  const std::size_t probe = std::max<std::size_t>(options.probe_chunks, 1);
  const bool probing = options.mode == RecordWriteMode::kProbe && writer.total() >= options.probe_min_bytes &&
                       writer.chunks() > 2 * probe;
  if (probing || direct) {
    AlignedBuffer buf = NewBuffer(options.chunk_bytes);
    const double buffered = probing ? writer.TimeChunks(0, probe, false, buf.get()) : 0.0;
    next = probing ? probe : 0;
    const std::size_t count = std::min(probe, writer.chunks() - next);
    const double through = writer.TimeChunks(next, count, true, buf.get());
    direct = std::isfinite(through) && (!probing || through < buffered);
    next += count;
  }
  if (!writer.SetDirect(direct)) direct = false;
  writer.WriteAll(next, direct);
  if (!writer.SetDirect(false) || ::ftruncate(out_fd, static_cast<off_t>(writer.total())) != 0) writer.Fail();
  return {writer.total(), direct};
}

}  // namespace al
