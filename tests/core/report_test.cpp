#include <fstream>

#include <gtest/gtest.h>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/report.hpp"
#include "test_data.hpp"

namespace al {
namespace {

TEST(Report, HasTheKeysEveryReportNeeds) {
  const auto report = NewReport("info");
  for (const char* key : {"status", "command", "params", "inputs", "counts", "timings_s", "warnings"})
    EXPECT_TRUE(report.contains(key)) << key;
  EXPECT_EQ(report["status"], "ok");
}

TEST(Report, Sha256OfKnownString) {
  const auto dir = test::TempDir();
  WriteFileAtomically(dir / "abc.txt", std::string("abc"));
  EXPECT_EQ(Sha256File(dir / "abc.txt"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(AtomicFile, FailedWriteLeavesNoFile) {
  const auto dir = test::TempDir();
  EXPECT_THROW(WriteFileAtomically(dir / "out.bin", [](std::ostream&) { throw Error("boom"); }), Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(AtomicFile, UnwritableDirectoryIsAnError) {
  EXPECT_THROW(WriteFileAtomically("/nonexistent_dir_al/x.bin", std::string("x")), Error);
}

}  // namespace
}  // namespace al
