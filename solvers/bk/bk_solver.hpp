// bk: the integral refinement problem (x_v in {(1,0),(0,1)}) solved exactly by one minimum cut
// (SPEC §5). p_v in {0, 1}. Options: none (an empty JSON object; any key is an error).
#pragma once
#include <memory>

#include <nlohmann/json.hpp>

#include "al/solver.hpp"

namespace al {

std::unique_ptr<Solver> MakeBkSolver(const nlohmann::json& options);

}  // namespace al
