// WriteKeptRecords against the plain concatenation (header + kept records in row order), in every
// write mode, with chunks small enough that runs, the header and the padded tail straddle them.
#include "al/io/kept_records_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "test_data.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kPrefix = 37;     // bytes before the records (a header the source skips)
constexpr std::size_t kRecord = 61;     // odd on purpose: no record boundary meets a chunk's

std::string RandomBytes(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (char& c : s) c = static_cast<char>(rng() & 0xff);
  return s;
}

std::string Expected(const std::string& header, const std::string& records, const std::vector<bool>& keep) {
  std::string out = header;
  for (std::size_t i = 0; i < keep.size(); ++i)
    if (keep[i]) out += records.substr(i * kRecord, kRecord);
  return out;
}

std::string ReadAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Source {
  fs::path path;
  std::string records;
  std::unique_ptr<RecordFile> file;
};

Source MakeSource(const fs::path& dir, std::size_t n) {
  Source s;
  s.path = dir / "source.bin";
  s.records = RandomBytes(n * kRecord, 7);
  std::ofstream(s.path, std::ios::binary) << RandomBytes(kPrefix, 3) << s.records;
  s.file = std::make_unique<RecordFile>(s.path.string(), kPrefix, n * kRecord);
  return s;
}

std::string WriteWith(const fs::path& out, const std::string& header, const Source& src,
                      const std::vector<bool>& keep, const KeptRecordsOptions& o, KeptRecordsSummary* summary = nullptr) {
  const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  EXPECT_GE(fd, 0);
  const KeptRecordsSummary s = WriteKeptRecords(fd, out.string(), header, *src.file, kRecord, keep, o);
  ::close(fd);
  if (summary) *summary = s;
  return ReadAll(out);
}

// Whether the folder's file system takes O_DIRECT (tmpfs before Linux 6.6 does not).
bool DirectIoWorks(const fs::path& dir) {
  const int fd = ::open((dir / "probe.bin").c_str(), O_WRONLY | O_CREAT | O_DIRECT | O_CLOEXEC, 0644);
  if (fd >= 0) ::close(fd);
  return fd >= 0;
}

std::vector<std::vector<bool>> Masks(std::size_t n) {
  std::mt19937 rng(11);
  std::vector<bool> random(n), alternate(n), none(n, false), all(n, true), tail_only(n, false), sparse(n), far(n);
  for (std::size_t i = 0; i < n; ++i) random[i] = rng() % 10 < 7, alternate[i] = i % 2 == 0;
  tail_only[n - 1] = true;
  // Runs read together in one span of the source: one kept record in three spans more than two
  // chunks' worth (the span is cut), and a gap of 1200 records (73 KB, over the 64 KB that one
  // span may skip) between runs that share an output chunk.
  for (std::size_t i = 0; i < n; ++i) sparse[i] = i % 3 == 0, far[i] = i < 500 || i == 1700 || (i >= 2000 && i % 3 != 0);
  return {random, alternate, none, all, tail_only, sparse, far};
}

TEST(KeptRecordsWriter, EveryModeWritesTheKeptRecordsInOrder) {
  const fs::path dir = test::TempDir();
  const std::size_t n = 3001;
  const Source src = MakeSource(dir, n);
  const bool direct_works = DirectIoWorks(dir);
  const std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex 7\n" + std::string(4100, 'h');
  for (RecordWriteMode mode : {RecordWriteMode::kBuffered, RecordWriteMode::kDirect, RecordWriteMode::kAdaptive})
    for (std::size_t chunk : {std::size_t{4096}, std::size_t{3 * 4096}})
      for (const std::vector<bool>& keep : Masks(n)) {
        KeptRecordsOptions o;
        o.mode = mode, o.chunk_bytes = chunk, o.adaptive_min_bytes = 0;
        KeptRecordsSummary s;
        const std::string got = WriteWith(dir / "out.bin", header, src, keep, o, &s);
        const std::string want = Expected(header, src.records, keep);
        ASSERT_EQ(got.size(), want.size()) << int(mode) << " chunk " << chunk;
        EXPECT_TRUE(got == want) << int(mode) << " chunk " << chunk;
        EXPECT_EQ(s.bytes, want.size());
        if (mode == RecordWriteMode::kBuffered) {
          EXPECT_EQ(s.direct_bytes, 0u);
        }
        if (mode == RecordWriteMode::kDirect && direct_works) {  // every whole chunk
          const std::size_t tail = want.size() % chunk;
          EXPECT_EQ(s.direct_bytes, want.size() - tail + (tail % 4096 == 0 ? tail : 0));
        }
      }
  fs::remove_all(dir);
}

TEST(KeptRecordsWriter, ShortHeaderAndNothingKept) {
  const fs::path dir = test::TempDir();
  const Source src = MakeSource(dir, 5);
  KeptRecordsOptions o;
  o.mode = RecordWriteMode::kDirect;
  EXPECT_EQ(WriteWith(dir / "a.bin", "hdr\n", src, std::vector<bool>(5, false), o), "hdr\n");
  EXPECT_EQ(WriteWith(dir / "b.bin", "", src, std::vector<bool>(5, false), o), "");
  fs::remove_all(dir);
}

TEST(KeptRecordsWriter, RefusesBadLayoutsAndAShrunkSource) {
  const fs::path dir = test::TempDir();
  const Source src = MakeSource(dir, 100);
  KeptRecordsOptions o;
  o.chunk_bytes = 5000;  // not a multiple of the alignment
  EXPECT_THROW(WriteWith(dir / "a.bin", "h", src, std::vector<bool>(100, true), o), Error);
  o = {};
  EXPECT_THROW(WriteWith(dir / "b.bin", "h", src, std::vector<bool>(101, true), o), Error);  // past the records
  fs::resize_file(src.path, kPrefix + 50 * kRecord);  // truncated in place after it was opened
  o.chunk_bytes = 4096;
  EXPECT_THROW(WriteWith(dir / "c.bin", "h", src, std::vector<bool>(100, true), o), Error);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace al
