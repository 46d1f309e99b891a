// RefineOptions' own table (al/refine/refine.hpp): the CLI's --method, --solver, --max-unmatched,
// --match-tol and --fgs-threshold and Python's keywords of the same names take their ranges and
// defaults from here, so both spell and default them alike.
#include <algorithm>

#include "al/refine/refine.hpp"
#include "al/refine/stages.hpp"
#include "al/solver.hpp"

namespace al {
namespace {

bool KnownSolver(const std::string& name) {
  const auto known = SolverNames();
  return std::find(known.begin(), known.end(), name) != known.end();
}

// The solver: a registered name, or empty for the default (ResolveSolverName). Reported, and
// shown as a default, under the name it resolves to.
OptionField<RefineOptions> SolverField() {
  std::string names;
  for (const auto& n : SolverNames()) names += (names.empty() ? "" : "|") + n;
  const std::string help = "which solver minimises the energy, docs/solvers.md";
  OptionField<RefineOptions> f{"solver", OptionType::kChoice, names, help, false, {}, {}, {}};
  f.get = [](const RefineOptions& o) { return nlohmann::json(ResolveSolverName(o.solver)); };
  f.in_range = [](const RefineOptions& o) { return o.solver.empty() || KnownSolver(o.solver); };
  f.set = [names, help](RefineOptions& o, const nlohmann::json& v) {  // the words of Check()
    const std::string name = v.get<std::string>();
    if (!KnownSolver(name)) throw OptionOutOfRange("refine", "solver", name, names, help);
    o.solver = name;
  };
  return f;
}

}  // namespace

const OptionTable<RefineOptions>& RefineOptions::Table() {
  static const auto table =
      OptionTable<RefineOptions>("refine")
          .Choice("method", &RefineOptions::method,
                  {{"fgs", "fgs"}, {"gg", "gg"}, {"sags", "sags"}, {"gc", "gc"}, {"generic", "generic"}},
                  "removal method preset: features, polarity and defaults of docs/methods.md")
          .Custom(SolverField())
          .Int("max_unmatched", &RefineOptions::max_unmatched, NumericRange::AtLeast(0),
               "subset-PLY rows allowed to stay unmatched")
          .Real("match_tol", &RefineOptions::match_tol, NumericRange::AtLeast(0),
                "tolerance pass for subset matching (0 = off)")
          .Real("fgs_threshold", &RefineOptions::fgs_threshold, NumericRange::Closed(0, 1),
                "FGS deletion threshold (a sum of softmax probabilities)");
  return table;
}

void RefineOptions::Check() const {
  graph.Check();
  decision.Check();
  Table().Check(*this);
}

}  // namespace al
