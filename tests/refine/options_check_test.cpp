// Check() of the refinement side's options structs (kNN, FGS mask, --auto grid, compare, sweep,
// synth): defaults pass; an out-of-range value is a usage error naming the option.
#include <gtest/gtest.h>

#include <functional>
#include <type_traits>

#include "al/core/error.hpp"
#include "al/fixtures/synth.hpp"
#include "al/graph/knn.hpp"
#include "al/refine/auto_tune.hpp"
#include "al/refine/compare.hpp"
#include "al/refine/fgs_mask.hpp"
#include "al/refine/sweep.hpp"

namespace al {
namespace {

template <class O>
void ExpectRefused(O options, const std::function<void(std::type_identity_t<O>&)>& spoil, const std::string& named) {
  EXPECT_NO_THROW(options.Check());
  spoil(options);
  try {
    options.Check();
    ADD_FAILURE() << "accepted, expected a message naming " << named;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::kUsage) << e.what();
    EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
  }
}

TEST(OptionsCheck, RefineSideStructsStateTheirRanges) {
  ExpectRefused<KnnOptions>({}, [](KnnOptions& o) { o.k = 0; }, "'k' = 0");
  ExpectRefused<KnnOptions>({}, [](KnnOptions& o) { o.checks = -5; }, "'checks' = -5");
  FgsMaskOptions fgs;
  fgs.positives = {0};
  ExpectRefused(fgs, [](FgsMaskOptions& o) { o.threshold = 1.5; }, "'threshold' = 1.5");
  ExpectRefused(fgs, [](FgsMaskOptions& o) { o.positives = {-1}; }, "'positive' = -1");
  ExpectRefused<AutoTuneOptions>({}, [](AutoTuneOptions& o) { o.lambda = {1, -2}; }, "'lambda' = -2");
  ExpectRefused<AutoTuneOptions>({}, [](AutoTuneOptions& o) { o.k.clear(); }, "empty grid");
  CompareOptions co;
  co.solvers = {"bk"};
  ExpectRefused(co, [](CompareOptions& o) { o.solvers = {"bk", "no-such"}; }, "no-such");
  ExpectRefused<fixtures::SynthOptions>({}, [](fixtures::SynthOptions& o) { o.sh_degree = 4; }, "--sh-degree");
}

TEST(OptionsCheck, SweepChecksItsScenesOptions) {
  SweepOptions o;
  o.out_dir = "out";
  o.scenes.push_back({"s", RefineOptions{}, "", ""});
  o.grid.k = {10};
  o.grid.delta = {0.8};
  o.grid.hops = {1};
  o.grid.radius_scale = {1};
  o.grid.lambda = {1};
  o.grid.solver = {"bk"};
  o.grid.threshold = {"0.5"};
  o.grid.segment_share = {0};
  ExpectRefused(o, [](SweepOptions& s) { s.scenes[0].options.graph.knn_checks = -5; }, "'knn_checks' = -5");
  ExpectRefused(o, [](SweepOptions& s) { s.solver_options = {{"cp", nlohmann::json::object()}}; }, "not a solver of the grid");
}

}  // namespace
}  // namespace al
