#include "al/core/text.hpp"

#include <cmath>
#include <sstream>

#include "al/core/error.hpp"

namespace al {

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

std::vector<std::string> SplitTrimmed(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) out.push_back(Trim(part));
  if (!s.empty() && s.back() == sep) out.push_back("");
  return out;
}

double ParseGridNumber(const std::string& key, const std::string& text) {
  const std::string t = Trim(text);
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(t, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (t.empty() || used != t.size() || !std::isfinite(v))
    throw Error("--grid: " + key + ": '" + t + "' is not a finite number", ExitCode::kUsage);
  return v;
}

}  // namespace al
