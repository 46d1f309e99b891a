// SolverResult's report forms (al/solver.hpp).
#include <cstdio>

#include "al/solver.hpp"

namespace al {

nlohmann::json SolverResult::ToJson() const {
  return {{"name", solver}, {"objective", objective}, {"iterations", iterations},
          {"converged", converged}, {"seconds", seconds}, {"stats", stats}};
}

std::string SolverResult::BriefReport() const {
  char line[160];
  std::snprintf(line, sizeof line, "%s: objective %.6g, %d iteration%s, %s, %.3f s", solver.c_str(), objective,
                iterations, iterations == 1 ? "" : "s", converged ? "converged" : "not converged", seconds);
  return line;
}

}  // namespace al
