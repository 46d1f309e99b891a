#include "src/cli/warnings.hpp"

#include <iostream>
#include <mutex>
#include <set>

namespace al::cli {

void PrintWarningOnce(const std::string& warning) {
  static std::mutex mutex;
  static std::set<std::string> printed;
  std::lock_guard<std::mutex> lock(mutex);
  if (printed.insert(warning).second) std::cerr << "warning: " << warning << std::endl;
}

void PrintReportWarnings(const nlohmann::json& report, const std::string& except) {
  const auto it = report.find("warnings");
  if (it == report.end() || !it->is_array()) return;
  for (const auto& w : *it)
    if (w.is_string() && w.get<std::string>() != except) PrintWarningOnce(w.get<std::string>());
}

}  // namespace al::cli
