#include "al/io/kept_records_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>

#include "al/core/error.hpp"

namespace al {
namespace {

struct Run {
  std::uint64_t out = 0, src = 0, bytes = 0;  // output offsets count the header
};

// Part of a run inside one output chunk: `bytes` from source offset `src` to chunk offset `at`.
struct Piece {
  std::uint64_t src = 0, bytes = 0, at = 0;
};

// Gaps of removed records up to this size are read and dropped rather than skipped by a new read.
constexpr std::uint64_t kMaxGap = std::uint64_t{64} << 10;
constexpr std::size_t kSpanFactor = 2;

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

// pwrite of len bytes at `at`; false (errno set) on failure.
bool WriteAt(int fd, const char* buf, std::size_t len, std::uint64_t at) {
  std::size_t done = 0;
  while (done < len) {
    const ssize_t got = ::pwrite(fd, buf + done, len - done, static_cast<off_t>(at + done));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    done += std::size_t(got);
  }
  return true;
}

// A second open file description of the same file, with O_DIRECT (-1 where refused). Opened
// through /proc/self/fd: the file already open, never a path another user could swap.
int DirectDescriptor(int fd) {
  const std::string self = "/proc/self/fd/" + std::to_string(fd);
  return ::open(self.c_str(), O_WRONLY | O_DIRECT | O_CLOEXEC);
}

// Which way each chunk is written. Buffered writes are fast while the kernel has warm pages and
// slow once it must take fresh ones (their speed changes during one file), so both ways keep a
// moving average of seconds per byte; the faster is used, the other retried every 16th chunk
// (64th when it is 3x slower or more).
class WayChooser {
 public:
  WayChooser(RecordWriteMode mode, bool direct_possible) : mode_(mode), direct_possible_(direct_possible) {}
  bool Direct() {
    std::lock_guard<std::mutex> lock(mu_);
    if (!direct_possible_ || mode_ == RecordWriteMode::kBuffered) return false;
    if (mode_ == RecordWriteMode::kDirect) return true;
    // Direct first: on a machine whose page cache must take fresh pages (every run of the 3M bench)
    // each buffered chunk costs about six direct ones, and both threads started buffered.
    for (const int w : {1, 0})
      if (count_[w] == 0) return w == 1;
    const bool better_direct = per_byte_[1] < per_byte_[0];
    // The slower way is retried now and then; rarely when it is far slower (each retry of buffered
    // writes into fresh pages cost five chunks' time at 3M: 557 MB in 0.21-0.25 s with a retry
    // every 64th chunk, 0.16-0.18 s direct only).
    const double ratio = per_byte_[!better_direct] / std::max(per_byte_[better_direct], 1e-300);
    return ++calls_ % (ratio < 3.0 ? 16 : 256) == 0 ? !better_direct : better_direct;
  }
  void Record(bool direct, double seconds, std::size_t bytes) {
    std::lock_guard<std::mutex> lock(mu_);
    const double x = seconds / double(std::max<std::size_t>(bytes, 1));
    double& e = per_byte_[direct];
    e = count_[direct]++ == 0 ? x : 0.7 * e + 0.3 * x;
    bytes_direct_ += direct ? bytes : 0;
  }
  void DirectRefused() {
    std::lock_guard<std::mutex> lock(mu_);
    direct_possible_ = false;
  }
  std::uint64_t bytes_direct() const { return bytes_direct_; }

 private:
  std::mutex mu_;
  RecordWriteMode mode_;
  bool direct_possible_;
  double per_byte_[2] = {0, 0};
  std::size_t count_[2] = {0, 0}, calls_ = 0;
  std::uint64_t bytes_direct_ = 0;
};

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

  // Chunk c's bytes into buf (chunk_ bytes, aligned); returns their count. Kept runs are short
  // where removals interleave (3M scene: 145k runs of ~17 records), and one pread each cost more
  // than the write itself, so runs with small gaps between them are read in one span into scratch
  // (at most kSpanFactor chunks) and copied out.
  std::size_t Fill(std::size_t c, char* buf, std::vector<char>& scratch) const {
    const std::uint64_t lo = std::uint64_t(c) * chunk_, hi = std::min<std::uint64_t>(lo + chunk_, total_);
    if (lo < header_.size()) std::memcpy(buf, header_.data() + lo, std::min<std::uint64_t>(hi, header_.size()) - lo);
    std::vector<Piece> pieces;
    auto it = std::upper_bound(runs_.begin(), runs_.end(), lo,
                               [](std::uint64_t x, const Run& r) { return x < r.out + r.bytes; });
    for (; it != runs_.end() && it->out < hi; ++it) {
      const std::uint64_t a = std::max(lo, it->out), b = std::min(hi, it->out + it->bytes);
      pieces.push_back({it->src + (a - it->out), b - a, a - lo});
    }
    scratch.resize(kSpanFactor * chunk_);
    for (std::size_t first = 0; first < pieces.size();) {
      std::size_t last = first + 1;
      while (last < pieces.size() && pieces[last].src - (pieces[last - 1].src + pieces[last - 1].bytes) <= kMaxGap &&
             pieces[last].src + pieces[last].bytes - pieces[first].src <= scratch.size())
        ++last;
      ReadPieces(pieces.data() + first, pieces.data() + last, buf, scratch);
      first = last;
    }
    return std::size_t(hi - lo);
  }

  // Chunk c, through direct_fd where the chooser says so (only whole aligned chunks can be).
  void WriteChunk(std::size_t c, char* buf, std::vector<char>& scratch, int direct_fd, WayChooser& way) const {
    const std::size_t len = Fill(c, buf, scratch);
    const bool direct = direct_fd >= 0 && len % kDirectAlignment == 0 && way.Direct();
    const double t = Now();
    if (WriteAt(direct ? direct_fd : fd_, buf, len, std::uint64_t(c) * chunk_)) {
      way.Record(direct, Now() - t, len);
      return;
    }
    if (!direct || errno != EINVAL) Fail();
    way.DirectRefused();  // the file system takes no O_DIRECT here after all
    if (!WriteAt(fd_, buf, len, std::uint64_t(c) * chunk_)) Fail();
  }

  // Pieces [first, last) of one chunk: one read of their source span, or straight into buf.
  void ReadPieces(const Piece* first, const Piece* last, char* buf, std::vector<char>& scratch) const {
    if (last - first == 1) {
      source_.Read(first->src, first->bytes, buf + first->at);
      return;
    }
    const std::uint64_t begin = first->src;
    source_.Read(begin, last[-1].src + last[-1].bytes - begin, scratch.data());
    for (const Piece* p = first; p != last; ++p) std::memcpy(buf + p->at, scratch.data() + (p->src - begin), p->bytes);
  }

  [[noreturn]] void Fail() const { throw FileError(path_, std::string("write failed: ") + std::strerror(errno)); }

  void WriteAll(int direct_fd, WayChooser& way) const;

 private:
  int fd_;
  const std::string& path_;
  const std::string& header_;
  const RecordFile& source_;
  std::vector<Run> runs_;
  std::size_t chunk_;
  std::uint64_t total_ = 0;
};

// The chunks shared between the threads, each with its own buffer.
void ChunkWriter::WriteAll(int direct_fd, WayChooser& way) const {
  const auto end = static_cast<std::int64_t>(chunks());
  std::exception_ptr error;
#pragma omp parallel
  {
    AlignedBuffer buf = NewBuffer(chunk_);
    std::vector<char> scratch;
#pragma omp for schedule(dynamic, 1)
    for (std::int64_t c = 0; c < end; ++c) {
      try {
        WriteChunk(std::size_t(c), buf.get(), scratch, direct_fd, way);
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
  const bool may_direct = options.mode == RecordWriteMode::kDirect ||
                          (options.mode == RecordWriteMode::kAdaptive && writer.total() >= options.adaptive_min_bytes);
  // Blocks allocated up front: buffered writes then skip delayed allocation (557 MB: 0.09 -> 0.05 s
  // warm), and direct writes within the file's size need not extend it. Refused (a file system
  // without fallocate) costs nothing: the writes allocate as they go.
  if (writer.total() > header.size()) (void)::fallocate(out_fd, 0, 0, static_cast<off_t>(writer.total()));
  const int direct_fd = may_direct ? DirectDescriptor(out_fd) : -1;
  WayChooser way(options.mode, direct_fd >= 0);
  try {
    writer.WriteAll(direct_fd, way);
  } catch (...) {
    if (direct_fd >= 0) ::close(direct_fd);
    throw;
  }
  if (direct_fd >= 0) ::close(direct_fd);
  if (::ftruncate(out_fd, static_cast<off_t>(writer.total())) != 0) writer.Fail();
  return {writer.total(), way.bytes_direct()};
}

}  // namespace al
