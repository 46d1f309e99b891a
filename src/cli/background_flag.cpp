#include "src/cli/background_flag.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "al/core/error.hpp"

namespace al::cli {

Eigen::Vector3f ParseBackground(const std::string& text) {
  std::vector<float> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stof(item, &used));
      if (used != item.size() || !std::isfinite(v.back())) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw Error("--bg: '" + text + "' is not 0, 1 or r,g,b", ExitCode::kUsage);
    }
  }
  if (v.size() == 1) return Eigen::Vector3f::Constant(v[0]);
  if (v.size() == 3) return Eigen::Vector3f(v[0], v[1], v[2]);
  throw Error("--bg: '" + text + "' is not 0, 1 or r,g,b", ExitCode::kUsage);
}

}  // namespace al::cli
