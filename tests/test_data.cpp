#include "test_data.hpp"

#include <unistd.h>

#include <cstdlib>
#include <fstream>

namespace al::test {

std::filesystem::path SharedDataDir() {
  namespace fs = std::filesystem;
  fs::path dir;
  if (const char* env = std::getenv("AL_TEST_DATA"); env && *env) {
    dir = env;
  } else {
    dir = fs::path(AL_SOURCE_DIR) / ".." / "shared" / "data";
  }
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return {};
  return fs::canonical(dir, ec);
}

std::filesystem::path TempDir() {
  namespace fs = std::filesystem;
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "al_test";
  for (char& c : name)
    if (c == '/') c = '_';
  fs::path dir = fs::temp_directory_path() / ("al_test_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void WriteText(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace al::test
