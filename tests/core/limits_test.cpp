// Memory bound (al/core/memory_limit.hpp) and special-file refusal (al/core/input_file.hpp).
#include <sys/stat.h>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/core/memory_limit.hpp"
#include "test_data.hpp"

namespace al {
namespace {

TEST(MemoryLimit, ParsesSizesAndRefusesNonsense) {
  EXPECT_EQ(ParseMemorySize("8G"), std::uint64_t(8) << 30);
  EXPECT_EQ(ParseMemorySize("512M"), std::uint64_t(512) << 20);
  EXPECT_EQ(ParseMemorySize("1.5GiB"), std::uint64_t(3) << 29);
  EXPECT_EQ(ParseMemorySize("300000000"), 300000000u);
  EXPECT_NEAR(double(ParseMemorySize("50%")), PhysicalMemoryBytes() / 2.0, 1.0);
  for (const char* bad : {"", "G", "-1G", "8X", "1M", "nan", "1e400"}) EXPECT_THROW(ParseMemorySize(bad), Error) << bad;
}

TEST(MemoryLimit, EstimatesOverTheLimitAreRefusedWithBothNumbers) {
  SetMemoryLimitBytes(std::uint64_t(1) << 30);
  EXPECT_NO_THROW(CheckMemoryEstimate("small", 1e6));
  try {
    CheckMemoryEstimate("render of view 'a'", 3.0 * (1 << 30));
    FAIL() << "not refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::kBadInput);
    EXPECT_NE(std::string(e.what()).find("3.0 GiB"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1.0 GiB"), std::string::npos) << e.what();
  }
  SetMemoryLimitBytes(0);  // back to the default
  EXPECT_EQ(MemoryLimitBytes(), PhysicalMemoryBytes() / 2);
}

TEST(InputFile, SpecialFilesAreRefusedBeforeAnyRead) {
  const auto dir = test::TempDir();
  const auto fifo = (dir / "pipe").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {fifo, std::string("/dev/zero"), dir.string()}) {
    try {
      ReadInputFile(path);  // a FIFO without a writer would block for ever in a plain open()
      FAIL() << path << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace al
