// View names become safe, unique file names (issue #14): NUL, '/', '\\', ':', control characters,
// "." and "..", repeats (also a repeat created by the renaming itself).
#include <set>

#include <gtest/gtest.h>

#include "al/io/cameras.hpp"

namespace al {
namespace {

TEST(Cameras, ViewNamesBecomeSafeAndUnique) {
  std::vector<Camera> cams(8);
  const std::vector<std::string> names = {"a/b", std::string("c\0d", 3), "a_b", "x", "x", "..", "", "ok"};
  for (std::size_t i = 0; i < cams.size(); ++i) cams[i].name = names[i];
  const auto warnings = MakeViewNamesSafe(cams);
  const std::vector<std::string> expect = {"a_b", "c_d", "a_b_2", "x", "x_2", "view", "view_2", "ok"};
  for (std::size_t i = 0; i < cams.size(); ++i) EXPECT_EQ(cams[i].name, expect[i]) << i;
  EXPECT_EQ(warnings.size(), 6u);  // every renamed view, none for "x" and "ok"
}

TEST(Cameras, SafeNamesAreBoundedAndRepeatsStillUnique) {
  std::vector<Camera> cams(3);
  for (auto& c : cams) c.name = std::string(300, 'v');
  MakeViewNamesSafe(cams);
  std::set<std::string> seen;
  for (const auto& c : cams) {
    EXPECT_LE(c.name.size(), 160u);
    EXPECT_TRUE(seen.insert(c.name).second) << c.name;
  }
}

}  // namespace
}  // namespace al
