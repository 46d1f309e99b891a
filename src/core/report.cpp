#include "al/core/report.hpp"

#include <openssl/evp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>

#include <algorithm>
#include <array>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/input_file.hpp"

namespace al {

nlohmann::json NewReport(const std::string& command) {
  return {{"status", "ok"},
          {"command", command},
          {"version", "0.1.0"},
          {"params", nlohmann::json::object()},
          {"inputs", nlohmann::json::object()},
          {"counts", nlohmann::json::object()},
          {"timings_s", nlohmann::json::object()},
          {"warnings", nlohmann::json::array()}};
}

std::string Sha256File(const std::filesystem::path& path, std::uintmax_t max_bytes, Links links) {
  const int fd = OpenRegularFile(path.string(), links);  // a FIFO or a device is refused, never read
  EVP_MD_CTX* ctx = EVP_MD_CTX_new();
  EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr);
  std::array<char, 1 << 16> buffer;
  for (std::uintmax_t left = max_bytes; left > 0;) {
    const ssize_t got = ::read(fd, buffer.data(), static_cast<std::size_t>(std::min<std::uintmax_t>(buffer.size(), left)));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    EVP_DigestUpdate(ctx, buffer.data(), static_cast<std::size_t>(got));
    left -= static_cast<std::uintmax_t>(got);
  }
  ::close(fd);
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_DigestFinal_ex(ctx, digest, &length);
  EVP_MD_CTX_free(ctx);
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (unsigned int i = 0; i < length; ++i) {
    out += hex[digest[i] >> 4];
    out += hex[digest[i] & 15];
  }
  return out;
}

void AddInputFile(nlohmann::json& report, const std::string& role, const std::filesystem::path& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  nlohmann::json entry = {{"path", path.string()}};
  if (!ec) {
    entry["bytes"] = size;
    if (size <= (64u << 20)) entry["sha256"] = Sha256File(path);
  }
  report["inputs"][role] = entry;
}

double PeakRssMiB() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

void WriteReport(const std::filesystem::path& dir, const nlohmann::json& report, const std::string& file_name) {
  EnsureDirectory(dir);
  // Memory is part of every claim about scale (3M-Gaussian runs must stay < 3x the scene size).
  nlohmann::json stamped = report;
  stamped["peak_rss_mib"] = PeakRssMiB();
  WriteFileAtomically(dir / file_name, stamped.dump(2) + "\n");
}

}  // namespace al
