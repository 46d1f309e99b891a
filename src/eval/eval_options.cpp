// EvalOptions::Check (al/eval/eval.hpp): every nested options struct states its own ranges.
#include "al/core/error.hpp"
#include "al/eval/eval.hpp"

namespace al::eval {

void EvalOptions::Check() const {
  if (out_dir.empty()) throw Error("eval: --out is required", ExitCode::kUsage);
  render.Check();
  ght.Check();
  float_depth.Check();
  if (const std::string problem = trust.Check(); !problem.empty()) throw Error("eval: " + problem, ExitCode::kUsage);
  semantic.Check();
  sim_sam.Check();
  feature.Check();
  residual.Check();
}

}  // namespace al::eval
