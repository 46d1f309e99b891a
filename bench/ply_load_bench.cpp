// PLY load throughput (SPEC §8): ReadPly on a generated >= 200 MB INRIA SH3 PLY, against a plain
// read() of the same file into memory (the I/O floor) in the same run. Both run from the page
// cache after the first iteration. The file is generated once (deterministic) and reused.
#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "al/io/ply.hpp"

namespace {

constexpr std::size_t kGaussians = 900'000;  // x 248 bytes = 223 MB

std::string BenchFile() {
  static const std::string path = [] {
    const auto dir = std::filesystem::temp_directory_path() / "al_ply_load_bench";
    std::filesystem::create_directories(dir);
    const auto file = dir / ("inria_sh3_" + std::to_string(kGaussians) + ".ply");
    if (std::filesystem::exists(file) &&
        std::filesystem::file_size(file) > kGaussians * 248) return file.string();
    al::Scene s;
    const auto n = static_cast<Eigen::Index>(kGaussians);
    s.sh_degree = 3;
    std::uint64_t state = 12345;  // LCG: deterministic, cheap
    auto next = [&state]() {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      return static_cast<float>((state >> 40) * 0x1.0p-24) * 2.0f - 1.0f;
    };
    s.means = al::MatX3f::NullaryExpr(n, 3, [&] { return 10.0f * next(); });
    s.log_scales = al::MatX3f::NullaryExpr(n, 3, [&] { return next() - 4.0f; });
    s.rotations = al::MatX4f::NullaryExpr(n, 4, next);
    s.opacity_logits = Eigen::VectorXf::NullaryExpr(n, next);
    s.sh = al::RowMatXf::NullaryExpr(n, 48, next);
    al::WritePly(file.string(), s);
    return file.string();
  }();
  return path;
}

void BM_ReadPly(benchmark::State& state) {
  const std::string path = BenchFile();
  const auto bytes = static_cast<std::int64_t>(std::filesystem::file_size(path));
  std::size_t n = 0;
  for (auto _ : state) {
    const al::Scene s = al::ReadPly(path);
    n = s.size();
    benchmark::DoNotOptimize(s.means.data());
  }
  state.SetBytesProcessed(state.iterations() * bytes);
  state.counters["gaussians"] = static_cast<double>(n);
}

// Baseline: read() the whole file into a buffer (what any loader must at least pay).
void BM_ReadFileBaseline(benchmark::State& state) {
  const std::string path = BenchFile();
  const auto bytes = static_cast<std::size_t>(std::filesystem::file_size(path));
  for (auto _ : state) {
    std::vector<char> buffer(bytes);
    const int fd = ::open(path.c_str(), O_RDONLY);
    std::size_t done = 0;
    while (done < bytes) {
      const ssize_t r = ::read(fd, buffer.data() + done, bytes - done);
      if (r <= 0) break;
      done += static_cast<std::size_t>(r);
    }
    ::close(fd);
    benchmark::DoNotOptimize(buffer.data());
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes));
}

BENCHMARK(BM_ReadFileBaseline)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_ReadPly)->Unit(benchmark::kMillisecond)->MinTime(1.0);

}  // namespace

BENCHMARK_MAIN();
