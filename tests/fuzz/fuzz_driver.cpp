// Standalone driver for libFuzzer-style targets when libFuzzer is unavailable (GCC builds):
// runs every seed file, then a fixed number of deterministic mutations of the seeds. A crash,
// sanitizer report or uncaught exception fails the ctest entry; no output means nothing found.
//   fuzz_<name> [--runs=N] [--seed=S] [seed files or directories...]
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

using Bytes = std::vector<std::uint8_t>;

struct Rng {  // SplitMix64: same sequence on every platform
  std::uint64_t s;
  std::uint64_t Next() {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::size_t Below(std::size_t n) { return n ? static_cast<std::size_t>(Next() % n) : 0; }
};

// Values that tend to break parsers: delimiters, digits, sign, extreme bytes.
constexpr std::uint8_t kInteresting[] = {0, 1, 0x7f, 0x80, 0xff, '\n', '\r', ' ', '-', '+', '.', 'e',
                                         '0', '1', '9', 'n', 'a', 'i'};

void Mutate(Bytes& b, Rng& rng) {
  switch (rng.Below(8)) {
    case 0:  // flip a bit
      if (!b.empty()) b[rng.Below(b.size())] ^= static_cast<std::uint8_t>(1u << rng.Below(8));
      break;
    case 1:  // set an interesting byte
      if (!b.empty()) b[rng.Below(b.size())] = kInteresting[rng.Below(sizeof kInteresting)];
      break;
    case 2:  // random byte
      if (!b.empty()) b[rng.Below(b.size())] = static_cast<std::uint8_t>(rng.Next());
      break;
    case 3:  // insert
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(rng.Below(b.size() + 1)), kInteresting[rng.Below(sizeof kInteresting)]);
      break;
    case 4: {  // erase a range
      if (b.empty()) break;
      const std::size_t at = rng.Below(b.size());
      const std::size_t len = 1 + rng.Below(std::min<std::size_t>(16, b.size() - at));
      b.erase(b.begin() + static_cast<std::ptrdiff_t>(at), b.begin() + static_cast<std::ptrdiff_t>(at + len));
      break;
    }
    case 5:  // truncate
      b.resize(rng.Below(b.size() + 1));
      break;
    case 6: {  // duplicate a chunk somewhere else
      if (b.empty() || b.size() > 65536) break;
      const std::size_t at = rng.Below(b.size());
      const std::size_t len = 1 + rng.Below(std::min<std::size_t>(64, b.size() - at));
      const Bytes chunk(b.begin() + static_cast<std::ptrdiff_t>(at), b.begin() + static_cast<std::ptrdiff_t>(at + len));
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(rng.Below(b.size() + 1)), chunk.begin(), chunk.end());
      break;
    }
    default: {  // rewrite a run of digits (element counts, indices) with a random number
      if (b.empty()) break;
      std::size_t at = rng.Below(b.size());
      while (at < b.size() && !(b[at] >= '0' && b[at] <= '9')) ++at;
      if (at == b.size()) break;
      std::size_t end = at;
      while (end < b.size() && b[end] >= '0' && b[end] <= '9') ++end;
      const std::uint64_t choices[] = {0, 1, 2, 3, 9, 45, 255, 4294967295ull, 18446744073709551615ull, rng.Next() % 100000};
      const std::string digits = std::to_string(choices[rng.Below(std::size(choices))]);
      b.erase(b.begin() + static_cast<std::ptrdiff_t>(at), b.begin() + static_cast<std::ptrdiff_t>(end));
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), digits.begin(), digits.end());
    }
  }
}

void Run(const Bytes& b) {
  // Copy into an exactly sized heap buffer so a sanitizer catches any read past the end.
  std::vector<std::uint8_t> exact(b);
  exact.shrink_to_fit();
  LLVMFuzzerTestOneInput(exact.empty() ? nullptr : exact.data(), exact.size());
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t runs = 2000;
  std::uint64_t seed = 1;
  std::vector<Bytes> seeds;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg.rfind("--runs=", 0) == 0) { runs = std::stoull(arg.substr(7)); continue; }
    if (arg.rfind("--seed=", 0) == 0) { seed = std::stoull(arg.substr(7)); continue; }
    std::vector<std::filesystem::path> files;
    if (std::filesystem::is_directory(arg)) {
      for (const auto& e : std::filesystem::directory_iterator(arg))
        if (e.is_regular_file()) files.push_back(e.path());
    } else if (std::filesystem::is_regular_file(arg)) {
      files.push_back(arg);
    } else {
      std::fprintf(stderr, "fuzz driver: no such seed file or directory: %s\n", arg.c_str());
      return 1;
    }
    std::sort(files.begin(), files.end());  // deterministic order
    for (const auto& f : files) {
      std::ifstream in(f, std::ios::binary);
      seeds.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
  }
  seeds.push_back({});  // the empty input is always a case
  for (const auto& s : seeds) Run(s);
  Rng rng{seed};
  for (std::size_t r = 0; r < runs; ++r) {
    Bytes b = seeds[rng.Below(seeds.size())];
    const std::size_t mutations = 1 + rng.Below(4);
    for (std::size_t m = 0; m < mutations; ++m) Mutate(b, rng);
    Run(b);
  }
  std::printf("fuzz driver: %zu seeds, %zu mutated inputs, no crash\n", seeds.size(), runs);
  return 0;
}
