// Locating the real data in ../shared/data for tests (never copied into the repo).
#pragma once
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace al::test {

// Directory of the shared test data: $AL_TEST_DATA, else <source>/../shared/data.
// Empty path when absent. With AL_REQUIRE_TEST_DATA=1 absence is a hard failure.
std::filesystem::path SharedDataDir();

// A fresh, empty temporary directory unique to the running test.
std::filesystem::path TempDir();

// A file's whole text (empty when missing), and writing one (parent folders created).
std::string ReadText(const std::filesystem::path& path);
void WriteText(const std::filesystem::path& path, const std::string& text);

}  // namespace al::test

// Skips the current test loudly when the shared data is missing (fails under AL_REQUIRE_TEST_DATA=1).
#define AL_REQUIRE_SHARED_DATA(dir_var)                                                         \
  const std::filesystem::path dir_var = ::al::test::SharedDataDir();                            \
  if (dir_var.empty()) {                                                                        \
    if (const char* req = std::getenv("AL_REQUIRE_TEST_DATA"); req && std::string(req) == "1") \
      FAIL() << "AL_REQUIRE_TEST_DATA=1 but the shared test data was not found "              \
                "(set AL_TEST_DATA or place shared/ beside the checkout)";                      \
    GTEST_SKIP() << "*** SKIPPED: shared test data not found (set AL_TEST_DATA) ***";           \
  }
