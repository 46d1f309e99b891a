// Cut pursuit for the simplex-constrained d1 problem (CUT_PURSUIT.md, "Cp_d1_lsx" re-implemented from
// the spec), D labels in general:
//   F(x) = sum_v w_v l_s(y_v, x_v) + sum_e w_e sum_d m_d |x_ud - x_vd| + sum_v i_simplex(x_v).
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "al/core/option_table.hpp"
#include "solvers/max_flow/max_flow.hpp"

namespace al::cp {

// Graph in forward-star form, every undirected edge stored once.
// What the solver reads: views of the arrays, so a caller that already holds them (the refine
// pipeline's RefineProblem) hands them over without a copy (685k nodes / 4M edges: 59 MB of peak RSS).
struct SimplexProblemView {
  std::int32_t D = 2;
  std::span<const std::int64_t> first_edge;    // V + 1
  std::span<const std::int32_t> adj_vertices;  // E
  std::span<const double> edge_weights;        // E
  std::span<const double> y;                   // V x D, rows on the simplex
  std::span<const double> node_weights;        // V (empty = all 1)
  std::span<const double> metric;              // D (empty = all 1)
  double loss = 0.1;                           // s: 0 linear, 1 quadratic, else smoothed KL

  std::int64_t num_nodes() const { return static_cast<std::int64_t>(first_edge.size()) - 1; }
};

struct SimplexProblem {
  std::int32_t D = 2;
  std::vector<std::int64_t> first_edge;    // V + 1
  std::vector<std::int32_t> adj_vertices;  // E
  std::vector<double> edge_weights;        // E
  std::vector<double> y;                   // V x D, rows on the simplex
  std::vector<double> node_weights;        // V (empty = all 1)
  std::vector<double> metric;              // D (empty = all 1)
  double loss = 0.1;                       // s: 0 linear, 1 quadratic, else smoothed KL

  std::int64_t num_nodes() const { return static_cast<std::int64_t>(first_edge.size()) - 1; }
  operator SimplexProblemView() const {  // NOLINT: a problem is read through its view
    return {D, first_edge, adj_vertices, edge_weights, y, node_weights, metric, loss};
  }
};

// Defaults = the upstream Python wrapper's (CUT_PURSUIT.md §2).
struct CutPursuitOptions {
  double cp_dif_tol = 1e-3;     // outer stop on mean l1 change; merge tolerance
  int cp_it_max = 10;           // maximum outer iterations
  int K = 2;                    // candidate directions per component (only 2 is implemented)
  int split_iter_num = 1;       // partition/update rounds per split
  double split_damp_ratio = 1;  // edge-capacity damping of the first round
  int split_values_init_num = 2;  // k-means++ restarts
  int split_values_iter_num = 2;  // Lloyd iterations per restart
  double pfdr_rho = 1.0;        // relaxation
  double pfdr_cond_min = 1e-2;  // preconditioner floor ratio
  double pfdr_dif_rcd = 0.0;    // reconditioning threshold (0 = never)
  double pfdr_dif_tol = -1.0;   // PFDR stop; < 0 means 1e-2 * cp_dif_tol
  int pfdr_it_max = 10000;      // PFDR maximum iterations
  int num_threads = 0;          // 0 = OpenMP default; results never depend on it
  bool emulate_upstream_projection_bug = false;  // reproduce pcp's polluted directions (§4.2)
  // Saturate the remainder of a split whose value then moved by <= cp_dif_tol (al-refine extension,
  // docs/solvers.md "cp speed"). false = the spec's rule only (saturated = no edge activated).
  bool saturate_split_remainders = true;
  // Max-flow algorithm of the splits (JSON "hybrid", "pseudoflow" or "bk"). All return the same cut;
  // BK alone is the pre-pseudoflow baseline of the benchmarks.
  MaxFlow::Algorithm max_flow = MaxFlow::Algorithm::kHybrid;
  // Solver of the reduced problem (§6): for D = 2 its exact optimum by level cuts on the reduced
  // graph, which §6.2 allows (JSON "level_sets", the default; docs/solvers.md "cp speed (3)"), or
  // PFDR ("pfdr", used for every D != 2).
  enum class Reduced { kLevelSets, kPfdr };
  Reduced reduced_solver = Reduced::kLevelSets;
  // Cold start: for D = 2 the level-set partition of §11 cut down to intervals of init_epsilon
  // (JSON "level_sets", the default; docs/solvers.md "cp speed (3)"), or the spec's single
  // component ("one_component", used for every D != 2 and for warm starts).
  enum class Init { kLevelSets, kOneComponent };
  Init init = Init::kLevelSets;
  double init_epsilon = 0.0;  // 0 = cp_dif_tol / 2 (docs/solvers.md "cp speed (3)")

  // The JSON keys of --solver-options, their ranges and help (cut_pursuit_solver.cpp).
  static const OptionTable<CutPursuitOptions>& Table();
  void Check() const { Table().Check(*this); }
};

struct CutPursuitResult {
  std::vector<std::int32_t> comp_assign;  // V
  std::vector<double> rX;                 // rV x D
  std::int32_t num_components = 0;
  std::vector<double> objective_history;  // Obj[0..it]
  std::vector<double> dif_history;        // Dif[1..it]
  std::vector<int> pfdr_iterations;       // per outer iteration (0 when solved by level sets)
  std::vector<std::int64_t> reduced_max_flows;  // per outer iteration (level-set reduced solves)
  // Wall seconds per outer iteration: split (directions + max-flows), reduced graph, PFDR, merge and
  // objective. Diagnostics only; never influence the result.
  std::vector<double> split_seconds, reduce_seconds, pfdr_seconds, merge_seconds;
  int iterations = 0;
  bool converged = false;
  double objective = 0.0;
  // Per outer iteration: vertices of the non-saturated components offered to the split (max-flow work).
  std::vector<std::int64_t> split_nodes;
  std::vector<char> saturated;            // per component at the end (not offered to a next split)
  int remainder_saturations = 0;          // components saturated by saturate_split_remainders
  std::vector<std::string> warnings;      // e.g. non-monotone objective steps above 1e-6 relative
  int non_monotone_steps = 0;             // every increase of F, however small
  // The level-set cold start (Init::kLevelSets): wall seconds, max-flows, pieces, plateau pieces.
  double init_seconds = 0.0;
  std::int64_t init_max_flows = 0, init_pieces = 0, init_plateaus = 0;

  double Value(std::int64_t v, int d, int D) const { return rX[comp_assign[v] * D + d]; }
};

// A starting iterate other than one component (al-refine extension; docs/solvers.md "Warm start"):
// comp[v] = v's component (any ids >= 0; -1 = a new node, which starts alone at its closed form),
// values = rV x D component values, saturated = per component (empty = none). A component with a
// new node or next to one starts unsaturated.
struct WarmStart {
  std::vector<std::int32_t> comp;
  std::vector<double> values;
  std::vector<char> saturated;
};

// Throws al::Error on an inconsistent problem (sizes, negative weights, non-finite data) or warm start.
CutPursuitResult RunCutPursuit(const SimplexProblemView& problem, const CutPursuitOptions& options,
                               const WarmStart* warm = nullptr);

// F(x) of the piecewise-constant solution, summed in a fixed order.
double SimplexObjective(const SimplexProblemView& problem, const std::vector<std::int32_t>& comp_assign,
                        const std::vector<double>& rX);

// Projection of a raw direction r onto the unit tangent cone of the simplex at X (§4.2).
// Writes z (unit l2 norm, or all zero when no feasible descent exists).
void ProjectDirection(const double* X, const double* r, int D, double eps, bool emulate_bug, double* z);

// Projection of X onto the simplex in the metric diag(gamma)^-1 (PFDR step 4).
void ProjectSimplexMetric(double* x, const double* gamma, int D);

}  // namespace al::cp
