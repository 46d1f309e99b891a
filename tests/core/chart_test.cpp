#include "al/core/chart.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_data.hpp"

namespace al {
namespace {
namespace fs = std::filesystem;

TEST(Chart, QuotesEmbeddedQuotes) { EXPECT_EQ(GnuplotQuote("it's"), "'it''s'"); }

TEST(Chart, DrawsAPngAndKeepsTheScript) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "gnuplot not installed";
  const fs::path dir = test::TempDir() / "chart";
  fs::create_directories(dir);
  {
    std::ofstream data(dir / "points.dat");
    data << "1 2\n2 3\n3 5\n";
  }
  const ChartResult r = DrawChart(dir / "line.png",
                                  "set terminal png size 320,240\nset output 'line.png'\n"
                                  "plot 'points.dat' using 1:2 with lines title 'a'\n");
  ASSERT_TRUE(r.drawn) << r.message;
  std::ifstream png(dir / "line.png", std::ios::binary);
  char magic[8] = {};
  png.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  EXPECT_TRUE(fs::exists(dir / "line.gp"));
  EXPECT_FALSE(fs::exists(dir / "line.png.tmp.png"));
}

TEST(Chart, AFailingScriptLeavesNoImageAndSaysWhy) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "gnuplot not installed";
  const fs::path dir = test::TempDir() / "chart_bad";
  fs::create_directories(dir);
  const ChartResult r = DrawChart(dir / "bad.png", "set terminal png\nset output 'bad.png'\nplot 'missing.dat'\n");
  EXPECT_FALSE(r.drawn);
  EXPECT_NE(r.message.find("gnuplot failed"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "bad.png"));
}

}  // namespace
}  // namespace al
