#include "al/core/memory_limit.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "al/core/error.hpp"

namespace al {
namespace {

std::uint64_t g_limit = 0;  // 0 = not set: the default

// cgroup v2 memory.max (or v1 limit_in_bytes); 0 when unlimited or unknown.
std::uint64_t CgroupLimit() {
  for (const char* file : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    std::ifstream in(file);
    std::string v;
    if (!(in >> v) || v == "max") continue;
    try {
      return std::stoull(v);
    } catch (const std::exception&) {
    }
  }
  return 0;
}

}  // namespace

std::uint64_t PhysicalMemoryBytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  std::uint64_t bytes = pages > 0 && page > 0 ? std::uint64_t(pages) * std::uint64_t(page) : (std::uint64_t(8) << 30);
  const std::uint64_t cgroup = CgroupLimit();
  if (cgroup > 0 && cgroup < bytes) bytes = cgroup;
  return bytes;
}

std::uint64_t MemoryLimitBytes() { return g_limit ? g_limit : PhysicalMemoryBytes() / 2; }

void SetMemoryLimitBytes(std::uint64_t bytes) { g_limit = bytes; }

std::uint64_t ParseMemorySize(const std::string& text) {
  const Error bad("--max-memory: '" + text + "' is not a size (e.g. 8G, 512M, 60%)", ExitCode::kUsage);
  std::size_t end = 0;
  double v = 0;
  try {
    v = std::stod(text, &end);
  } catch (const std::exception&) {
    throw bad;
  }
  std::string unit = text.substr(end);
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();
  if (unit.size() > 1 && unit.back() == 'I') unit.pop_back();
  double scale = 0;
  if (unit.empty()) scale = 1;
  else if (unit == "K") scale = 1024.0;
  else if (unit == "M") scale = 1024.0 * 1024;
  else if (unit == "G") scale = 1024.0 * 1024 * 1024;
  else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
  else if (unit == "%") scale = double(PhysicalMemoryBytes()) / 100.0;
  const double bytes = v * scale;
  if (scale == 0 || !std::isfinite(bytes) || bytes < 0) throw bad;
  if (bytes < double(64 << 20))
    throw Error("--max-memory: " + FormatBytes(bytes) + " is below the 64 MiB any run needs", ExitCode::kUsage);
  return bytes > 1.8e19 ? UINT64_MAX : static_cast<std::uint64_t>(bytes);
}

std::string FormatBytes(double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB"};
  int u = 0;
  while (bytes >= 1024.0 && u < 5) {
    bytes /= 1024.0;
    ++u;
  }
  char buf[48];
  std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", bytes, units[u]);
  return buf;
}

void CheckMemoryEstimate(const std::string& what, double bytes) {
  const double limit = double(MemoryLimitBytes());
  if (!(bytes > limit)) return;
  throw Error(what + " needs about " + FormatBytes(bytes) + ", over the memory limit of " + FormatBytes(limit) +
              " (--max-memory; the default is half of physical memory)");
}

}  // namespace al
