// --bg for the commands that render (render, eval): "0", "1" or "r,g,b", finite numbers only.
#pragma once
#include <string>

#include <Eigen/Core>

namespace al::cli {

// Throws al::Error (usage) naming the flag on anything else.
Eigen::Vector3f ParseBackground(const std::string& text);

}  // namespace al::cli
